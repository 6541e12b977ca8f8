//! A reader of the few SVG elements plotters writes (`text`, `rect`, `circle`), for tests that
//! check a figure's layout: where its labels stand, which rectangles and markers it draws and
//! in what order.

/// A `<text>` element: its anchor position, font size, whether it is rotated, and its text.
#[derive(Debug, Clone, PartialEq)]
pub struct SvgText {
    pub x: f64,
    pub y: f64,
    pub font_size: f64,
    pub rotated: bool,
    pub anchor: String,
    pub text: String,
}

impl SvgText {
    /// The horizontal extent of an unrotated text, estimated at 0.62 em per character (DejaVu
    /// Sans digits are 0.636 em, `.` 0.318 em, `e` 0.615 em).
    pub fn x_extent(&self) -> (f64, f64) {
        let w = 0.62 * self.font_size * self.text.chars().count() as f64;
        match self.anchor.as_str() {
            "middle" => (self.x - w / 2.0, self.x + w / 2.0),
            "end" => (self.x - w, self.x),
            _ => (self.x, self.x + w),
        }
    }
}

/// A `<rect>` element.
#[derive(Debug, Clone, PartialEq)]
pub struct SvgRect {
    pub x: f64,
    pub y: f64,
    pub width: f64,
    pub height: f64,
    pub fill: String,
}

/// A `<circle>` element.
#[derive(Debug, Clone, PartialEq)]
pub struct SvgCircle {
    pub cx: f64,
    pub cy: f64,
    pub r: f64,
    pub fill: String,
}

fn attr(tag: &str, name: &str) -> Option<String> {
    let key = format!(" {name}=\"");
    let start = tag.find(&key)? + key.len();
    let end = tag[start..].find('"')? + start;
    Some(tag[start..end].to_string())
}

fn num(tag: &str, name: &str) -> f64 {
    attr(tag, name)
        .and_then(|v| v.parse().ok())
        .unwrap_or(f64::NAN)
}

/// Every `<text>`, in document order.
pub fn texts(svg: &str) -> Vec<SvgText> {
    let mut out = Vec::new();
    let mut rest = svg;
    while let Some(i) = rest.find("<text ") {
        let tag_end = rest[i..].find('>').unwrap() + i;
        let tag = &rest[i..tag_end];
        let close = rest[tag_end..].find("</text>").unwrap() + tag_end;
        out.push(SvgText {
            x: num(tag, "x"),
            y: num(tag, "y"),
            font_size: num(tag, "font-size"),
            rotated: tag.contains("rotate("),
            anchor: attr(tag, "text-anchor").unwrap_or_default(),
            text: rest[tag_end + 1..close]
                .trim()
                .replace("&apos;", "'")
                .replace("&lt;", "<")
                .replace("&gt;", ">")
                .replace("&amp;", "&"),
        });
        rest = &rest[close..];
    }
    out
}

/// Every `<rect>`, in document order.
pub fn rects(svg: &str) -> Vec<SvgRect> {
    elements(svg, "<rect ")
        .map(|tag| SvgRect {
            x: num(tag, "x"),
            y: num(tag, "y"),
            width: num(tag, "width"),
            height: num(tag, "height"),
            fill: attr(tag, "fill").unwrap_or_default(),
        })
        .collect()
}

/// Every `<circle>`, in document order (later ones are drawn over earlier ones).
pub fn circles(svg: &str) -> Vec<SvgCircle> {
    elements(svg, "<circle ")
        .map(|tag| SvgCircle {
            cx: num(tag, "cx"),
            cy: num(tag, "cy"),
            r: num(tag, "r"),
            fill: attr(tag, "fill").unwrap_or_default(),
        })
        .collect()
}

fn elements<'a>(svg: &'a str, open: &'a str) -> impl Iterator<Item = &'a str> + 'a {
    svg.match_indices(open).map(move |(i, _)| {
        let end = svg[i..].find('>').unwrap() + i;
        &svg[i..end]
    })
}
