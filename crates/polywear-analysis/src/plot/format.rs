//! The file format of a figure, chosen by the caller (a command's `--format`, or the fixed PNG of
//! a command without one) and carried with the figure's path down to the backend: the backend is
//! picked by the format, never by reading the path's extension.

use std::path::{Path, PathBuf};

use polywear_core::named_enum;

named_enum! {
    /// A figure's file format: the file's extension is its name.
    #[derive(Default)]
    pub enum FigureFormat: "figure format" {
        /// A PNG bitmap, through plotters' bitmap backend (the default of `--format`).
        #[default]
        Png,
        /// An SVG document (vector text and shapes, for reports and slides), through plotters'
        /// SVG backend.
        Svg,
    }
}

impl FigureFormat {
    /// Every format, in the order `--format` lists them.
    pub const ALL: [FigureFormat; 2] = [FigureFormat::Png, FigureFormat::Svg];

    /// The extension of the format's files, without the dot (`png`, `svg`).
    pub fn ext(self) -> &'static str {
        self.as_str()
    }

    /// The format whose extension `path` ends in (exactly, as `--plot` accepts it), if any: for
    /// a path a user names in full.
    pub fn of_path(path: &Path) -> Option<FigureFormat> {
        let ext = path.extension()?.to_str()?;
        FigureFormat::ALL.into_iter().find(|f| f.ext() == ext)
    }
}

/// A figure's file: where it is written and in which format it is drawn.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct FigureFile {
    /// The file.
    pub path: PathBuf,
    /// The format it is drawn in.
    pub format: FigureFormat,
}

impl FigureFile {
    /// `dir/stem.ext`, with the format's extension.
    pub fn named(dir: &Path, stem: &str, format: FigureFormat) -> FigureFile {
        FigureFile {
            path: dir.join(format!("{stem}.{}", format.ext())),
            format,
        }
    }

    /// `path` with its extension replaced by the format's (`Path::with_extension`).
    pub fn beside(path: &Path, format: FigureFormat) -> FigureFile {
        FigureFile {
            path: path.with_extension(format.ext()),
            format,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_are_extensions() {
        assert_eq!(FigureFormat::Png.ext(), "png");
        assert_eq!(FigureFormat::Svg.ext(), "svg");
        assert_eq!("svg".parse::<FigureFormat>(), Ok(FigureFormat::Svg));
        assert!("SVG".parse::<FigureFormat>().is_err());
        assert_eq!(
            FigureFormat::of_path(Path::new("a/b.svg")),
            Some(FigureFormat::Svg)
        );
        assert_eq!(
            FigureFormat::of_path(Path::new("a/b.png")),
            Some(FigureFormat::Png)
        );
        assert_eq!(FigureFormat::of_path(Path::new("a/b.PNG")), None);
        assert_eq!(FigureFormat::of_path(Path::new("a/b")), None);
        let f = FigureFile::named(Path::new("d"), "riskmap_x_y", FigureFormat::Svg);
        assert_eq!(f.path, Path::new("d/riskmap_x_y.svg"));
        let f = FigureFile::beside(Path::new("d/chart.parquet"), FigureFormat::Png);
        assert_eq!(f.path, Path::new("d/chart.png"));
    }
}
