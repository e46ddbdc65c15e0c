//! Figures: the one module that renders plotters drawings as PNG or SVG (the embedded font,
//! each figure's size and resolution, PNG encoding, atomic writes), with what every drawing
//! shares: lengths in CSS pixels scaled to the resolution ([`Scale`]), text measured and wrapped
//! in the figure font ([`text`]) and axis ticks ([`ticks`]). Phase diagrams, curve plots, the
//! lattice gas' space-time picture and the per-job figures draw; this module renders.
//!
//! **Sizes.** Every drawing is laid out in CSS pixels (96 per inch) and draws each length, font
//! size and line width through the [`Scale`] it is handed: 1 for SVG (vector) and for PNG at
//! 96 dpi, dpi / 96 for PNG at other resolutions (`--dpi 192`: twice the pixels each way, the
//! same picture). A [`Sizing`] is what a command asks for: a size in CSS pixels (or each
//! figure's own) and the PNG's resolution.

pub mod raster;
pub mod text;
pub mod ticks;

use plotters::chart::MeshStyle;
use plotters::coord::Shift;
use plotters::coord::ranged1d::Ranged;
use plotters::prelude::*;
use raster::Raster;
use std::ops::RangeInclusive;
use std::path::Path;

/// The error of drawing on backend `B`.
pub type DrawingError<B> = DrawingAreaErrorKind<<B as DrawingBackend>::ErrorType>;

/// The font family every figure draws its text in (the embedded DejaVu Sans).
pub const FONT: &str = "sans-serif";

/// The resolution at which one CSS pixel is one pixel of the PNG.
pub const CSS_DPI: f64 = 96.0;

/// Allowed picture widths and heights in CSS pixels, and PNG resolutions in dots per inch.
pub const WIDTHS: RangeInclusive<u32> = 300..=8000;
pub const HEIGHTS: RangeInclusive<u32> = 200..=8000;
pub const DPIS: RangeInclusive<f64> = 24.0..=600.0;

/// The embedded DejaVu Sans (`src/figure/fonts`, free licence in its `LICENSE`): figures need
/// no system fonts. A proportional face, whose digits and full stop stand apart at 11 px (the
/// monospaced face before left the stop adrift in a wide cell).
pub const FONT_BYTES: &[u8] = include_bytes!("figure/fonts/DejaVuSans.ttf");

/// Register the embedded font as [`FONT`] with plotters (which lays out and measures text
/// with it, and draws it in SVG; PNGs draw it through [`raster`]). Called before anything
/// draws or measures text.
pub fn register_font() {
    static ONCE: std::sync::Once = std::sync::Once::new();
    ONCE.call_once(|| {
        let _ = plotters::style::register_font(FONT, FontStyle::Normal, FONT_BYTES);
    });
}

/// What a command asks of its figures: their size in CSS pixels (None: each figure's own) and
/// the PNG resolution (SVG is vector and has none). Checked by the command line against
/// [`WIDTHS`], [`HEIGHTS`] and [`DPIS`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sizing {
    pub width: Option<u32>,
    pub height: Option<u32>,
    pub dpi: f64,
}

impl Default for Sizing {
    /// Each figure's own size at 96 dpi (the per-job figures written at the end of a job).
    fn default() -> Self {
        Sizing {
            width: None,
            height: None,
            dpi: CSS_DPI,
        }
    }
}

impl Sizing {
    /// The size in CSS pixels of a figure whose own size is `natural`.
    pub fn css(&self, natural: (u32, u32)) -> (u32, u32) {
        (
            self.width.unwrap_or(natural.0),
            self.height.unwrap_or(natural.1),
        )
    }

    /// The scale of the PNG: device pixels per CSS pixel.
    pub fn scale(&self) -> Scale {
        Scale(self.dpi / CSS_DPI)
    }
}

/// Device pixels per CSS pixel. Every length a drawing uses (positions, margins, label areas,
/// font sizes, line widths, marker radii) is written in CSS pixels and goes through here.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Scale(pub f64);

impl Scale {
    /// One device pixel per CSS pixel (SVG; PNG at 96 dpi).
    pub const CSS: Scale = Scale(1.0);

    /// A length in CSS pixels in device pixels (rounded).
    pub fn px(self, css: impl Into<f64>) -> i32 {
        (css.into() * self.0).round() as i32
    }

    /// A size in CSS pixels in device pixels (rounded, not negative).
    pub fn upx(self, css: impl Into<f64>) -> u32 {
        self.px(css).max(0) as u32
    }

    /// A point in CSS pixels in device pixels.
    pub fn at(self, (x, y): (i32, i32)) -> (i32, i32) {
        (self.px(x), self.px(y))
    }

    /// A line width in CSS pixels in device pixels, at least one.
    pub fn line(self, css: f64) -> u32 {
        ((css * self.0).round() as u32).max(1)
    }

    /// The figure font at `size` CSS pixels.
    pub fn font(self, size: f64) -> FontDesc<'static> {
        (FONT, size * self.0).into_font()
    }

    /// A length in device pixels in CSS pixels.
    pub fn css(self, device: impl Into<f64>) -> f64 {
        device.into() / self.0
    }
}

/// The styles every chart's mesh shares, scaled: tick labels at `label` CSS pixels, axis
/// descriptions one pixel larger, axis and grid lines and tick marks.
pub fn mesh_style<'m, 'a, 'b, X, Y, DB>(
    mesh: &'m mut MeshStyle<'a, 'b, X, Y, DB>,
    s: Scale,
    label: f64,
) -> &'m mut MeshStyle<'a, 'b, X, Y, DB>
where
    X: Ranged,
    Y: Ranged,
    DB: DrawingBackend,
{
    mesh.label_style(s.font(label))
        .axis_desc_style(s.font(label + 1.0))
        .axis_style(BLACK.stroke_width(s.line(1.0)))
        .bold_line_style(BLACK.mix(0.2).stroke_width(s.line(1.0)))
        .light_line_style(BLACK.mix(0.1).stroke_width(s.line(1.0)))
        .set_all_tick_mark_size(s.px(5))
}

/// Encode 8-bit RGB pixels (rows top to bottom) as a PNG.
pub fn encode_png(rgb: &[u8], w: u32, h: u32) -> anyhow::Result<Vec<u8>> {
    let mut out = Vec::new();
    {
        let mut encoder = png::Encoder::new(&mut out, w, h);
        encoder.set_color(png::ColorType::Rgb);
        encoder.set_depth(png::BitDepth::Eight);
        let mut writer = encoder.write_header()?;
        writer.write_image_data(rgb)?;
        writer.finish()?;
    }
    Ok(out)
}

/// The pixels of a PNG of `css` CSS pixels at `scale`.
pub fn device_size((w, h): (u32, u32), scale: Scale) -> (u32, u32) {
    (scale.upx(w).max(1), scale.upx(h).max(1))
}

/// Draw a picture of `css` CSS pixels at `scale` on a white bitmap and write it to `path` as
/// PNG (atomically).
pub fn save_png<F>(path: &Path, css: (u32, u32), scale: Scale, draw: F) -> anyhow::Result<()>
where
    F: FnOnce(&DrawingArea<Raster<'_>, Shift>, Scale) -> Result<(), DrawingError<Raster<'static>>>,
{
    let bytes =
        render_png(css, scale, draw).map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))?;
    crate::fs::write_atomic(path, &bytes)?;
    Ok(())
}

/// Draw a picture of `css` CSS pixels at `scale` on a white bitmap and return it encoded as
/// PNG (for files and for pages that inline their figures).
pub fn render_png<F>(css: (u32, u32), scale: Scale, draw: F) -> anyhow::Result<Vec<u8>>
where
    F: FnOnce(&DrawingArea<Raster<'_>, Shift>, Scale) -> Result<(), DrawingError<Raster<'static>>>,
{
    let (w, h) = device_size(css, scale);
    let rgb = render_rgb((w, h), scale, draw)?;
    encode_png(&rgb, w, h)
}

/// Draw a picture of `w` x `h` device pixels at `scale` on a white bitmap; its RGB bytes.
pub fn render_rgb<F>((w, h): (u32, u32), scale: Scale, draw: F) -> anyhow::Result<Vec<u8>>
where
    F: FnOnce(&DrawingArea<Raster<'_>, Shift>, Scale) -> Result<(), DrawingError<Raster<'static>>>,
{
    register_font();
    let mut buf = vec![255u8; (w as usize) * (h as usize) * 3];
    {
        let root = Raster::new(BitMapBackend::with_buffer(&mut buf, (w, h))).into_drawing_area();
        draw(&root, scale).map_err(|e| anyhow::anyhow!("drawing: {e}"))?;
        root.present()
            .map_err(|e| anyhow::anyhow!("drawing: {e}"))?;
    }
    Ok(buf)
}

/// Draw a picture of `css` CSS pixels as SVG and write it to `path` (atomically).
pub fn save_svg<F>(path: &Path, css: (u32, u32), draw: F) -> anyhow::Result<()>
where
    F: FnOnce(
        &DrawingArea<SVGBackend<'_>, Shift>,
        Scale,
    ) -> Result<(), DrawingError<SVGBackend<'static>>>,
{
    let text = render_svg(css, draw).map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))?;
    crate::fs::write_atomic(path, text.as_bytes())?;
    Ok(())
}

/// Draw a picture of `css` CSS pixels as SVG (scale 1) and return its text.
pub fn render_svg<F>(css: (u32, u32), draw: F) -> anyhow::Result<String>
where
    F: FnOnce(
        &DrawingArea<SVGBackend<'_>, Shift>,
        Scale,
    ) -> Result<(), DrawingError<SVGBackend<'static>>>,
{
    register_font();
    let mut text = String::new();
    {
        let root = SVGBackend::with_string(&mut text, css).into_drawing_area();
        draw(&root, Scale::CSS).map_err(|e| anyhow::anyhow!("drawing: {e}"))?;
        root.present()
            .map_err(|e| anyhow::anyhow!("drawing: {e}"))?;
    }
    Ok(text)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_scale_turns_css_pixels_into_device_pixels() {
        let s = Sizing {
            dpi: 192.0,
            ..Sizing::default()
        }
        .scale();
        assert_eq!(s.px(11), 22);
        assert_eq!(s.at((3, -4)), (6, -8));
        assert_eq!(s.line(0.2), 1, "a line never vanishes");
        assert_eq!(device_size((820, 560), s), (1640, 1120));
        assert_eq!(Sizing::default().css((820, 560)), (820, 560));
        let given = Sizing {
            width: Some(400),
            ..Sizing::default()
        };
        assert_eq!(given.css((820, 560)), (400, 560));
    }
}

/// The colour of a label's marker (the fill of filled markers, the line of open ones); the
/// per-job figures colour labels the same way.
pub fn marker_colour(label: &str) -> RGBColor {
    match label {
        "plug" | "steady" => RGBColor(31, 119, 180),
        "s-wave" | "density waves" | "minimum" | "accelerating" => RGBColor(214, 39, 40),
        "slug" | "s-wave+slug" => RGBColor(44, 160, 44),
        "wavy-slug" | "mixed" | "maximum" | "jammed" => RGBColor(255, 127, 14),
        "homogeneous" | "not-steady" | "no waves" | "monotonic" => RGBColor(120, 120, 120),
        _ => RGBColor(148, 103, 189),
    }
}
