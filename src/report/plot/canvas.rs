//! The font, the bitmap backend that draws the plots' text with it, and
//! the PNG encoder.

use super::FAMILY;
use ab_glyph::{Font as _, FontRef, PxScale, ScaleFont as _};
use plotters::prelude::*;
use plotters_backend::text_anchor::{HPos, VPos};
use plotters_backend::{
    BackendColor, BackendCoord, BackendStyle, BackendTextStyle, DrawingErrorKind,
};
use std::path::PathBuf;
use std::sync::OnceLock;

/// The largest font size, at most `size`, at which `text` is at most
/// `width` pixels wide (never below 10).
pub(super) fn fit(font: &FontRef<'static>, text: &str, size: u32, width: u32) -> u32 {
    let mut s = size;
    while s > 10 && text_width(font, f64::from(s), text) > f64::from(width) {
        s -= 1;
    }
    s
}

/// Width in pixels of `text` at `size`.
pub(super) fn text_width(font: &FontRef<'static>, size: f64, text: &str) -> f64 {
    let font = font.as_scaled(PxScale::from(size as f32));
    let mut caret = 0.0f32;
    let mut prev = None;
    for c in text.chars() {
        let id = font.glyph_id(c);
        if let Some(p) = prev {
            caret += font.kern(p, id);
        }
        caret += font.h_advance(id);
        prev = Some(id);
    }
    f64::from(caret)
}

/// The bitmap backend with its own text rendering. (`plotters`' `ab_glyph`
/// renderer, in 0.3.7, drops each glyph's side bearing, which gives uneven
/// letter spacing, and puts the baseline half the font size below the
/// anchor, which lifts tick labels off their grid lines; here glyphs are
/// placed at their outline bounds. Tried and kept for issue 25: with
/// `plotters`' own text the plots read "candi dates", "lambda _n".) Layout and
/// drawing share one measure, so labels sit where plotters expects them.
pub(super) struct Canvas<'a> {
    pub(super) inner: BitMapBackend<'a>,
    pub(super) font: &'static FontRef<'static>,
}

impl Canvas<'_> {
    /// Layout box of `text`: width (advances and kerning) and height
    /// (ascent to descent), with the baseline at `ascent` below the top.
    fn layout(&self, text: &str, size: f64) -> (i32, i32, f32) {
        let scaled = self.font.as_scaled(PxScale::from(size as f32));
        let w = text_width(self.font, size, text).ceil() as i32;
        let h = (scaled.ascent() - scaled.descent()).ceil() as i32;
        (w, h, scaled.ascent())
    }
}

impl DrawingBackend for Canvas<'_> {
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
    /// A thick polyline segment by segment, with round joins: the backend's
    /// mitred joins shoot spikes (past the axes) where the line turns back.
    fn draw_path<S: BackendStyle, I: IntoIterator<Item = BackendCoord>>(
        &mut self,
        path: I,
        style: &S,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        let points: Vec<BackendCoord> = path.into_iter().collect();
        let width = style.stroke_width();
        if width <= 1 || points.len() <= 2 {
            return self.inner.draw_path(points, style);
        }
        for w in points.windows(2) {
            self.inner.draw_path(w.iter().copied(), style)?;
        }
        for &p in &points[1..points.len() - 1] {
            self.inner.draw_circle(p, width / 2, style, true)?;
        }
        Ok(())
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

    fn estimate_text_size<TStyle: BackendTextStyle>(
        &self,
        text: &str,
        style: &TStyle,
    ) -> Result<(u32, u32), DrawingErrorKind<Self::ErrorType>> {
        let (w, h, _) = self.layout(text, style.size());
        Ok((w.max(0) as u32, h.max(0) as u32))
    }

    fn draw_text<TStyle: BackendTextStyle>(
        &mut self,
        text: &str,
        style: &TStyle,
        pos: BackendCoord,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        let color = style.color();
        if color.alpha == 0.0 {
            return Ok(());
        }
        let size = style.size();
        let (w, h, ascent) = self.layout(text, size);
        // Offsets of the layout box's top-left corner from the anchor.
        let dx = match style.anchor().h_pos {
            HPos::Left => 0,
            HPos::Right => -w,
            HPos::Center => -w / 2,
        };
        let dy = match style.anchor().v_pos {
            VPos::Top => 0,
            VPos::Center => -h / 2,
            VPos::Bottom => -h,
        };
        let transform = style.transform();
        let font = self.font.as_scaled(PxScale::from(size as f32));
        let mut caret = 0.0f32;
        let mut prev = None;
        for c in text.chars() {
            let id = font.glyph_id(c);
            if let Some(p) = prev {
                caret += font.kern(p, id);
            }
            prev = Some(id);
            let glyph = id.with_scale_and_position(
                PxScale::from(size as f32),
                ab_glyph::point(caret, ascent),
            );
            caret += font.h_advance(id);
            let Some(outline) = self.font.outline_glyph(glyph) else {
                continue;
            };
            let bounds = outline.px_bounds();
            let mut pixels = Vec::new();
            outline.draw(|x, y, coverage| {
                if coverage > 0.0 {
                    let px = bounds.min.x as i32 + x as i32 + dx;
                    let py = bounds.min.y as i32 + y as i32 + dy;
                    pixels.push((transform.transform(px, py), coverage));
                }
            });
            for ((x, y), coverage) in pixels {
                let c = BackendColor {
                    alpha: color.alpha * f64::from(coverage.min(1.0)),
                    rgb: color.rgb,
                };
                self.inner.draw_pixel((pos.0 + x, pos.1 + y), c)?;
            }
        }
        Ok(())
    }
}

pub(super) fn encode_png(rgb: &[u8], width: u32, height: u32) -> Result<Vec<u8>, String> {
    let mut out = Vec::new();
    {
        let mut enc = png::Encoder::new(&mut out, width, height);
        enc.set_color(png::ColorType::Rgb);
        enc.set_depth(png::BitDepth::Eight);
        let mut w = enc
            .write_header()
            .map_err(|e| format!("PNG encoding: {e}"))?;
        w.write_image_data(rgb)
            .map_err(|e| format!("PNG encoding: {e}"))?;
        w.finish().map_err(|e| format!("PNG encoding: {e}"))?;
    }
    Ok(out)
}

/// Candidate font files, in order.
pub(super) fn font_candidates() -> Vec<PathBuf> {
    let mut v = Vec::new();
    if let Some(p) = std::env::var_os("UBR_PLOT_FONT") {
        v.push(PathBuf::from(p));
    }
    for p in [
        "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf",
        "/usr/share/fonts/truetype/liberation2/LiberationSans-Regular.ttf",
        "/usr/share/fonts/truetype/liberation/LiberationSans-Regular.ttf",
        "/usr/share/fonts/truetype/freefont/FreeSans.ttf",
        "/usr/share/fonts/dejavu/DejaVuSans.ttf",
        "/usr/share/fonts/TTF/DejaVuSans.ttf",
    ] {
        v.push(PathBuf::from(p));
    }
    v
}

/// Loads the font once per process, and registers it with `plotters` too
/// (for the layout code that asks it directly).
pub(super) fn load_font() -> Result<&'static FontRef<'static>, String> {
    static FONT: OnceLock<Result<FontRef<'static>, String>> = OnceLock::new();
    FONT.get_or_init(|| {
        let (bytes, font) = read_font(&font_candidates())?;
        plotters::style::register_font(FAMILY, FontStyle::Normal, bytes)
            .map_err(|_| "the plot font is not usable".to_string())?;
        Ok(font)
    })
    .as_ref()
    .map_err(Clone::clone)
}

/// The first candidate that is a usable font, kept for the life of the
/// process (plotters wants `'static` font data).
pub(super) fn read_font(
    candidates: &[PathBuf],
) -> Result<(&'static [u8], FontRef<'static>), String> {
    let mut tried = Vec::new();
    for p in candidates {
        match std::fs::read(p) {
            Ok(bytes) if FontRef::try_from_slice(&bytes).is_ok() => {
                let bytes: &'static [u8] = Box::leak(bytes.into_boxed_slice());
                if let Ok(font) = FontRef::try_from_slice(bytes) {
                    return Ok((bytes, font));
                }
            }
            Ok(_) => tried.push(format!("{} (not a usable font)", p.display())),
            Err(e) => tried.push(format!("{} ({e})", p.display())),
        }
    }
    Err(format!(
        "no font to draw plots with: install Debian's fonts-dejavu-core, or set \
         UBR_PLOT_FONT to a .ttf file; tried {}",
        tried.join(", ")
    ))
}
