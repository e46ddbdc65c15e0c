//! The backend of PNG figures: plotters' bitmap, with text drawn from the embedded font's
//! glyph outlines, each glyph at its pen position with its side bearing, on a whole-pixel
//! baseline. plotters'
//! own text drawing puts each glyph's ink at the pen position (dropping the left side
//! bearing) and rounds vertical offsets toward zero: a full stop sat glued to the digit
//! before it and up to a pixel high, and "0.25" read "0 25" at 96 dpi. Lines, shapes and
//! pixels are plotters' bitmap's own.

use ab_glyph::{Font, FontRef, ScaleFont, point};
use plotters::prelude::BitMapBackend;
use plotters_backend::text_anchor::{HPos, VPos};
use plotters_backend::{
    BackendColor, BackendCoord, BackendStyle, BackendTextStyle, DrawingBackend, DrawingErrorKind,
};
use std::sync::OnceLock;

/// The embedded font's outlines.
fn font() -> &'static FontRef<'static> {
    static FONT: OnceLock<FontRef<'static>> = OnceLock::new();
    FONT.get_or_init(|| FontRef::try_from_slice(super::FONT_BYTES).expect("the embedded font"))
}

/// The height of the box of a line of text at `size` pixels, as plotters reckons it (so that
/// the label areas of its charts fit as before).
fn box_height(size: f64) -> f64 {
    size / 1.24
}

/// The depth of the baseline in that box: digits (0.63 of the size tall in DejaVu Sans) sit
/// in its middle.
fn baseline(size: f64) -> f64 {
    (0.5 * box_height(size) + 0.313 * size).round()
}

/// The advance width of `text` at `size` pixels: the glyphs' advances and kerning.
pub fn advance(text: &str, size: f64) -> f64 {
    let scaled = font().as_scaled(size as f32);
    let mut pen = 0f32;
    let mut prev = None;
    for c in text.chars() {
        let id = scaled.glyph_id(c);
        if let Some(p) = prev {
            pen += scaled.kern(p, id);
        }
        pen += scaled.h_advance(id);
        prev = Some(id);
    }
    f64::from(pen)
}

/// The ink of `text` at `size` pixels: (x, y, coverage) from the top left of its box, each
/// glyph at its pen position (fractional: even spacing) on a whole-pixel baseline.
fn ink(text: &str, size: f64, mut pixel: impl FnMut(i32, i32, f32)) {
    let scaled = font().as_scaled(size as f32);
    let base = baseline(size) as f32;
    let mut pen = 0f32;
    let mut prev = None;
    for c in text.chars() {
        let id = scaled.glyph_id(c);
        if let Some(p) = prev {
            pen += scaled.kern(p, id);
        }
        let glyph = id.with_scale_and_position(size as f32, point(pen, base));
        if let Some(outline) = font().outline_glyph(glyph) {
            let b = outline.px_bounds();
            outline.draw(|x, y, c| pixel(b.min.x as i32 + x as i32, b.min.y as i32 + y as i32, c));
        }
        pen += scaled.h_advance(id);
        prev = Some(id);
    }
}

/// plotters' bitmap backend with the text of the figure font drawn by [`ink`].
pub struct Raster<'a> {
    inner: BitMapBackend<'a>,
}

impl<'a> Raster<'a> {
    pub fn new(inner: BitMapBackend<'a>) -> Self {
        Raster { inner }
    }
}

/// Whether a text style is in the figure font (every text of the figures is).
fn ours<S: BackendTextStyle>(style: &S) -> bool {
    style.family().as_str() == super::FONT
}

impl DrawingBackend for Raster<'_> {
    type ErrorType = <BitMapBackend<'static> as DrawingBackend>::ErrorType;

    fn get_size(&self) -> (u32, u32) {
        self.inner.get_size()
    }

    fn ensure_prepared(&mut self) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.inner.ensure_prepared()
    }

    fn present(&mut self) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.inner.present()
    }

    fn draw_pixel(
        &mut self,
        point: BackendCoord,
        color: BackendColor,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.inner.draw_pixel(point, color)
    }

    fn draw_line<S: BackendStyle>(
        &mut self,
        from: BackendCoord,
        to: BackendCoord,
        style: &S,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.inner.draw_line(from, to, style)
    }

    fn draw_rect<S: BackendStyle>(
        &mut self,
        upper_left: BackendCoord,
        bottom_right: BackendCoord,
        style: &S,
        fill: bool,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.inner.draw_rect(upper_left, bottom_right, style, fill)
    }

    fn draw_path<S: BackendStyle, I: IntoIterator<Item = BackendCoord>>(
        &mut self,
        path: I,
        style: &S,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.inner.draw_path(path, style)
    }

    fn draw_circle<S: BackendStyle>(
        &mut self,
        center: BackendCoord,
        radius: u32,
        style: &S,
        fill: bool,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.inner.draw_circle(center, radius, style, fill)
    }

    fn fill_polygon<S: BackendStyle, I: IntoIterator<Item = BackendCoord>>(
        &mut self,
        vert: I,
        style: &S,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.inner.fill_polygon(vert, style)
    }

    fn blit_bitmap(
        &mut self,
        pos: BackendCoord,
        size: (u32, u32),
        src: &[u8],
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.inner.blit_bitmap(pos, size, src)
    }

    fn estimate_text_size<S: BackendTextStyle>(
        &self,
        text: &str,
        style: &S,
    ) -> Result<(u32, u32), DrawingErrorKind<Self::ErrorType>> {
        if !ours(style) {
            return self.inner.estimate_text_size(text, style);
        }
        let size = style.size();
        Ok((
            advance(text, size).ceil() as u32,
            box_height(size).round() as u32,
        ))
    }

    fn draw_text<S: BackendTextStyle>(
        &mut self,
        text: &str,
        style: &S,
        pos: BackendCoord,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        let color = style.color();
        if !ours(style) || color.alpha == 0.0 {
            return self.inner.draw_text(text, style, pos);
        }
        let size = style.size();
        let (w, h) = (advance(text, size), box_height(size));
        let anchor = style.anchor();
        let dx = match anchor.h_pos {
            HPos::Left => 0.0,
            HPos::Center => -0.5 * w,
            HPos::Right => -w,
        }
        .round() as i32;
        let dy = match anchor.v_pos {
            VPos::Top => 0.0,
            VPos::Center => -0.5 * h,
            VPos::Bottom => -h,
        }
        .round() as i32;
        let transform = style.transform();
        let (width, height) = self.get_size();
        let mut result = Ok(());
        ink(text, size, |x, y, coverage| {
            if coverage <= 0.0 || result.is_err() {
                return;
            }
            let (x, y) = transform.transform(x + dx, y + dy);
            let (x, y) = (pos.0 + x, pos.1 + y);
            if x >= 0 && y >= 0 && x < width as i32 && y < height as i32 {
                result = self.inner.draw_pixel(
                    (x, y),
                    BackendColor {
                        alpha: color.alpha * f64::from(coverage.min(1.0)),
                        rgb: color.rgb,
                    },
                );
            }
        });
        result
    }
}
