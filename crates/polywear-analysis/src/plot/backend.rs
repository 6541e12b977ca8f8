//! One drawing backend for every figure, picked by its [`FigureFormat`]: PNG through plotters'
//! bitmap backend, SVG through its SVG backend (vector text and shapes, for
//! reports and slides). Each drawing call is handed to the backend it wraps, so a figure's code
//! is written once for both formats. Both draw into memory (`FigureBuffer`); the file is
//! written by [`polywear_study::safe_write`], so a figure never follows a link planted at its name.

use plotters::prelude::{BitMapBackend, SVGBackend};
use plotters_backend::{
    BackendColor, BackendCoord, BackendStyle, BackendTextStyle, DrawingBackend, DrawingErrorKind,
};

use super::FigureFormat;

/// A PNG or SVG backend.
pub(crate) enum FigureBackend<'a> {
    /// A PNG bitmap.
    Png(BitMapBackend<'a>),
    /// An SVG document.
    Svg(SVGBackend<'a>),
}

/// A figure's pixels or SVG text, drawn in memory before its file is written.
pub(crate) enum FigureBuffer {
    /// RGB pixels of a PNG figure, and its size.
    Png(Vec<u8>, (u32, u32)),
    /// The SVG document.
    Svg(String, (u32, u32)),
}

impl FigureBuffer {
    /// An empty figure of `size` pixels in `format`.
    pub fn new(format: FigureFormat, size: (u32, u32)) -> FigureBuffer {
        match format {
            FigureFormat::Svg => FigureBuffer::Svg(String::new(), size),
            FigureFormat::Png => {
                FigureBuffer::Png(vec![0; 3 * size.0 as usize * size.1 as usize], size)
            }
        }
    }

    /// The backend that draws into this buffer.
    pub fn backend(&mut self) -> FigureBackend<'_> {
        match self {
            FigureBuffer::Png(pixels, size) => {
                FigureBackend::Png(BitMapBackend::with_buffer(pixels, *size))
            }
            FigureBuffer::Svg(text, size) => {
                FigureBackend::Svg(SVGBackend::with_string(text, *size))
            }
        }
    }

    /// The file's bytes: the pixels encoded as plotters' file backend encodes them (the `image`
    /// crate's PNG encoder at its defaults), or the SVG text.
    pub fn into_bytes(self) -> Result<Vec<u8>, FigureError> {
        match self {
            FigureBuffer::Png(pixels, (w, h)) => {
                use image::ImageEncoder;
                let mut out = Vec::new();
                image::codecs::png::PngEncoder::new(&mut out)
                    .write_image(&pixels, w, h, image::ColorType::Rgb8)
                    .map_err(|e| FigureError(e.to_string()))?;
                Ok(out)
            }
            FigureBuffer::Svg(text, _) => Ok(text.into_bytes()),
        }
    }
}

/// The error of either backend, as text.
#[derive(Debug)]
pub(crate) struct FigureError(pub String);

impl std::fmt::Display for FigureError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for FigureError {}

fn lift<E: std::error::Error + Send + Sync>(
    e: DrawingErrorKind<E>,
) -> DrawingErrorKind<FigureError> {
    match e {
        DrawingErrorKind::DrawingError(e) => {
            DrawingErrorKind::DrawingError(FigureError(e.to_string()))
        }
        DrawingErrorKind::FontError(e) => DrawingErrorKind::FontError(e),
    }
}

/// Calls the same method on whichever backend is inside, lifting its error.
macro_rules! each {
    ($self:ident, $b:ident => $call:expr) => {
        match $self {
            FigureBackend::Png($b) => $call.map_err(lift),
            FigureBackend::Svg($b) => $call.map_err(lift),
        }
    };
}

type Drawn<T = ()> = Result<T, DrawingErrorKind<FigureError>>;

impl DrawingBackend for FigureBackend<'_> {
    type ErrorType = FigureError;

    fn get_size(&self) -> (u32, u32) {
        match self {
            FigureBackend::Png(b) => b.get_size(),
            FigureBackend::Svg(b) => b.get_size(),
        }
    }

    fn ensure_prepared(&mut self) -> Drawn {
        each!(self, b => b.ensure_prepared())
    }

    fn present(&mut self) -> Drawn {
        each!(self, b => b.present())
    }

    fn draw_pixel(&mut self, point: BackendCoord, color: BackendColor) -> Drawn {
        each!(self, b => b.draw_pixel(point, color))
    }

    fn draw_line<S: BackendStyle>(
        &mut self,
        from: BackendCoord,
        to: BackendCoord,
        style: &S,
    ) -> Drawn {
        each!(self, b => b.draw_line(from, to, style))
    }

    fn draw_rect<S: BackendStyle>(
        &mut self,
        upper_left: BackendCoord,
        bottom_right: BackendCoord,
        style: &S,
        fill: bool,
    ) -> Drawn {
        each!(self, b => b.draw_rect(upper_left, bottom_right, style, fill))
    }

    fn draw_path<S: BackendStyle, I: IntoIterator<Item = BackendCoord>>(
        &mut self,
        path: I,
        style: &S,
    ) -> Drawn {
        each!(self, b => b.draw_path(path, style))
    }

    fn draw_circle<S: BackendStyle>(
        &mut self,
        center: BackendCoord,
        radius: u32,
        style: &S,
        fill: bool,
    ) -> Drawn {
        each!(self, b => b.draw_circle(center, radius, style, fill))
    }

    fn fill_polygon<S: BackendStyle, I: IntoIterator<Item = BackendCoord>>(
        &mut self,
        vert: I,
        style: &S,
    ) -> Drawn {
        each!(self, b => b.fill_polygon(vert, style))
    }

    fn draw_text<T: BackendTextStyle>(
        &mut self,
        text: &str,
        style: &T,
        pos: BackendCoord,
    ) -> Drawn {
        each!(self, b => b.draw_text(text, style, pos))
    }

    fn estimate_text_size<T: BackendTextStyle>(&self, text: &str, style: &T) -> Drawn<(u32, u32)> {
        each!(self, b => b.estimate_text_size(text, style))
    }

    fn blit_bitmap(&mut self, pos: BackendCoord, size: (u32, u32), src: &[u8]) -> Drawn {
        each!(self, b => b.blit_bitmap(pos, size, src))
    }
}
