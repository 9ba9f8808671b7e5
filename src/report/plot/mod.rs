//! PNG plots for a person to look at: the contact-surface plot (pressure,
//! and with friction the tangential traction and the friction bound,
//! against the position along the surface, with the Hertz curve) and
//! residual histories on a log scale.
//!
//! Plots are drawn with `plotters` into an in-memory RGB bitmap and encoded
//! with `png`; the file is written atomically (a temporary `.png` file in the
//! same directory, then a rename), so a failed plot leaves nothing behind.
//!
//! # Font
//! Text is rasterised in pure Rust with `ab_glyph` (through a thin wrapper
//! of `plotters`' bitmap backend that places glyphs by their outline bounds,
//! which `plotters`' own `ab_glyph` text does not, giving uneven spacing),
//! from a TrueType font read at run time: the file named by the environment
//! variable `UBR_PLOT_FONT` if set, else Debian's `fonts-dejavu-core`
//! (`/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf`), else a few other
//! common sans-serif fonts. No font found gives an error that says so (never
//! a panic); nothing is linked against fontconfig or freetype.
//!
//! # Data
//! Points with a non-finite coordinate (or one beyond 1e300 in magnitude)
//! are dropped, and on a log axis so are points with a non-positive value (and
//! values more than 250 decades below the largest); a line is broken where
//! points are dropped (a NaN between two points breaks it on purpose). If
//! `x` and `y` differ in length the extra values are ignored. With a given x
//! range ([`Axes::x_range`]) what lies outside is cut off: points dropped,
//! lines cut at the border; the y range is that of what remains.
//! Empty series, or no drawable point at all, give a plot with empty axes
//! (marked "no data"), never a panic.

use super::write_atomic;
use ab_glyph::{Font as _, FontRef, PxScale, ScaleFont as _};
use plotters::coord::combinators::LogCoord;
use plotters::coord::ranged1d::BoldPoints;
use plotters::coord::types::RangedCoordf64;
use plotters::coord::Shift;
use plotters::element::DashedPathElement;
use plotters::prelude::*;
use plotters::style::text_anchor;
use plotters_backend::text_anchor::{HPos, VPos};
use plotters_backend::{
    BackendColor, BackendCoord, BackendStyle, BackendTextStyle, DrawingErrorKind,
};
use std::ops::Range;
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

/// Image size in pixels.
const WIDTH: u32 = 1200;
const HEIGHT: u32 = 800;
/// Font sizes in pixels.
const TITLE_SIZE: u32 = 32;
const LABEL_SIZE: u32 = 24;
const TICK_SIZE: u32 = 19;
const LEGEND_SIZE: u32 = 20;
/// Most labelled ticks per axis.
const X_TICKS: usize = 10;
const Y_TICKS: usize = 10;
/// The family name the font is registered under.
const FAMILY: &str = "ubr-sans";

/// One curve or point set.
#[derive(Clone, Copy, Debug)]
pub struct Series<'a> {
    /// Shown in the legend (an empty label leaves the series out of it).
    pub label: &'a str,
    pub x: &'a [f64],
    pub y: &'a [f64],
    pub style: Style,
}

/// How a series is drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Style {
    /// A filled circle per point.
    Points,
    /// A solid polyline.
    Line,
    /// A dashed polyline (e.g. an analytic reference curve).
    DashedLine,
    /// A hollow circle per point (scattered values drawn over others).
    Rings,
}

/// How the axes are chosen, beyond the data.
#[derive(Clone, Debug, Default)]
pub struct Axes {
    /// The x range shown (data bounds when None); what lies outside is cut off.
    pub x_range: Option<Range<f64>>,
    /// A linear y axis that always shows 0 (a contact pressure: a nearly
    /// constant one is then not magnified into noise).
    pub y_from_zero: bool,
}

/// Line plot with a title, axis labels and a legend, e.g. the
/// contact-surface plot: pressure (and with friction |tangential traction|
/// and the friction bound) against the position along the surface, with the
/// Hertz curve as a [`Style::DashedLine`]. With `log_y` the y axis is
/// logarithmic (non-positive values are dropped). Atomic.
pub fn plot_lines(
    path: &Path,
    title: &str,
    x_label: &str,
    y_label: &str,
    series: &[Series],
    log_y: bool,
) -> Result<(), String> {
    plot_with_axes(
        path,
        title,
        x_label,
        y_label,
        series,
        log_y,
        &Axes::default(),
    )
}

/// [`plot_lines`] with the axes chosen by `axes`. Atomic.
pub fn plot_with_axes(
    path: &Path,
    title: &str,
    x_label: &str,
    y_label: &str,
    series: &[Series],
    log_y: bool,
    axes: &Axes,
) -> Result<(), String> {
    let png = render(title, x_label, y_label, series, log_y, axes)
        .map_err(|e| format!("cannot draw plot '{}': {e}", path.display()))?;
    write_atomic(path, &png).map_err(|e| format!("cannot write plot '{}': {e}", path.display()))
}

/// Convergence plot: each `(label, values)` against `iterations`, as lines
/// on a logarithmic y axis (zeros and negative values are dropped). Atomic.
pub fn plot_history(
    path: &Path,
    title: &str,
    iterations: &[f64],
    series: &[(&str, &[f64])],
) -> Result<(), String> {
    let s: Vec<Series> = series
        .iter()
        .map(|&(label, y)| Series {
            label,
            x: iterations,
            y,
            style: Style::Line,
        })
        .collect();
    plot_lines(path, title, "iteration", "residual", &s, true)
}

/// One curve of `-plot_history`.
#[derive(Clone, Debug, PartialEq)]
pub struct HistoryCurve {
    pub label: String,
    /// A value per iteration (NaN where there is none).
    pub y: Vec<f64>,
    /// Dashed: a target, not a history.
    pub dashed: bool,
}

/// The curves of `-plot_history` from the history of a run (per
/// iteration: the paper's change (4.16)/(5.6), NaN where it was not
/// computed; the constraint residual; the error estimate of lambda, NaN
/// under the paper's stop): the change where it exists (else, as one point,
/// `final_change`, the change of the last iteration computed after the
/// loop of a condensed run), the residual, and under the accuracy stop
/// (`accuracy`: `-ubr_lambda_rtol`) the estimate and the target that stops
/// the run, `lambda_rtol / 4`, or with `coulomb` the target of CF-FP's last
/// Tresca solves, `lambda_rtol / 40`.
pub fn history_curves(
    history: &[[f64; 3]],
    final_change: Option<f64>,
    accuracy: Option<f64>,
    coulomb: bool,
) -> Vec<HistoryCurve> {
    let column = |c: usize| -> Vec<f64> { history.iter().map(|h| h[c]).collect() };
    let curve = |label: &str, y: Vec<f64>, dashed: bool| HistoryCurve {
        label: label.to_string(),
        y,
        dashed,
    };
    let mut out = Vec::new();
    let mut change = column(0);
    if change.iter().any(|x| x.is_finite() && *x > 0.0) {
        out.push(curve("relative change (4.16)/(5.6)", change, false));
    } else if let (Some(last), Some(c)) = (change.last_mut(), final_change) {
        if c.is_finite() && c > 0.0 {
            *last = c;
            out.push(curve(
                "relative change (4.16)/(5.6), at the end only",
                change,
                false,
            ));
        }
    }
    out.push(curve("constraint residual ||Bu - phi||", column(1), false));
    if let Some(tol) = accuracy {
        out.push(curve(
            "estimated error of lambda (relative, max norm)",
            column(2),
            false,
        ));
        let (target, label) = if coulomb {
            (
                tol / 40.0,
                format!(
                    "the last Tresca solves stop below -ubr_lambda_rtol/40 = {:.1e}",
                    tol / 40.0
                ),
            )
        } else {
            (
                tol / 4.0,
                format!(
                    "stop: estimate below -ubr_lambda_rtol/4 = {:.1e}",
                    tol / 4.0
                ),
            )
        };
        out.push(curve(&label, vec![target; history.len()], true));
    }
    out
}

/// A series after dropping the points that cannot be drawn: runs of
/// consecutive drawable points.
#[derive(Clone, Debug)]
struct Clean {
    runs: Vec<Vec<(f64, f64)>>,
}

/// `c` cut to `x` in `range`: points outside dropped; with `line`, each
/// segment cut at the border (a run that leaves the range ends there).
fn clip_x(c: Clean, range: &Range<f64>, line: bool) -> Clean {
    let (lo, hi) = (range.start, range.end);
    let inside = |x: f64| x >= lo && x <= hi;
    let mut runs = Vec::new();
    for run in c.runs {
        let mut cur: Vec<(f64, f64)> = Vec::new();
        if !line || run.len() == 1 {
            for &(x, y) in &run {
                if inside(x) {
                    cur.push((x, y));
                }
            }
            if !cur.is_empty() {
                runs.push(cur);
            }
            continue;
        }
        for w in run.windows(2) {
            let ((x0, y0), (x1, y1)) = (w[0], w[1]);
            // The parameters t in [0, 1] of the segment within the range.
            let (mut t0, mut t1) = (0.0f64, 1.0f64);
            let dx = x1 - x0;
            if dx == 0.0 {
                if !inside(x0) {
                    t0 = 1.0;
                    t1 = 0.0;
                }
            } else {
                let (ta, tb) = ((lo - x0) / dx, (hi - x0) / dx);
                t0 = t0.max(ta.min(tb));
                t1 = t1.min(ta.max(tb));
            }
            if t0 > t1 {
                if !cur.is_empty() {
                    runs.push(std::mem::take(&mut cur));
                }
                continue;
            }
            let at = |t: f64| {
                if t == 0.0 {
                    (x0, y0)
                } else if t == 1.0 {
                    (x1, y1)
                } else {
                    (x0 + t * dx, y0 + t * (y1 - y0))
                }
            };
            if cur.is_empty() {
                cur.push(at(t0));
            }
            cur.push(at(t1));
            if t1 < 1.0 {
                runs.push(std::mem::take(&mut cur));
            }
        }
        if !cur.is_empty() {
            runs.push(cur);
        }
    }
    Clean { runs }
}

/// Largest magnitude drawn: beyond it axis widths would overflow.
const MAX_ABS: f64 = 1e300;
/// Most decades a log axis spans (plotters' log ticks need a finite ratio).
const MAX_DECADES: f64 = 250.0;

/// Drops the points that cannot be drawn: non-finite or beyond [`MAX_ABS`];
/// with `log_y`, y values not above `floor` (at least 0).
fn clean(s: &Series, log_y: bool, floor: f64) -> Clean {
    let mut runs = Vec::new();
    let mut run = Vec::new();
    let ok = |v: f64| v.is_finite() && v.abs() <= MAX_ABS;
    for (&x, &y) in s.x.iter().zip(s.y) {
        if ok(x) && ok(y) && (!log_y || y > floor.max(0.0)) {
            run.push((x, y));
        } else if !run.is_empty() {
            runs.push(std::mem::take(&mut run));
        }
    }
    if !run.is_empty() {
        runs.push(run);
    }
    Clean { runs }
}

/// An axis range around `[lo, hi]` (data bounds, or None without data),
/// padded by `pad_lo`/`pad_hi` of its width (of its decades when `log`).
fn axis_range(bounds: Option<(f64, f64)>, log: bool, pad_lo: f64, pad_hi: f64) -> Range<f64> {
    if log {
        let (lo, hi) = match bounds {
            Some((lo, hi)) => (lo.log10(), hi.log10()),
            None => (-1.0, 1.0),
        };
        let (lo, hi) = if hi - lo < 1e-9 {
            (lo - 1.0, hi + 1.0)
        } else {
            (lo, hi)
        };
        let w = hi - lo;
        let r = 10f64.powf(lo - pad_lo * w)..10f64.powf(hi + pad_hi * w);
        if r.start > 0.0 && r.end.is_finite() && r.start < r.end {
            r
        } else {
            10f64.powf(lo)..10f64.powf(hi)
        }
    } else {
        let (lo, hi) = bounds.unwrap_or((0.0, 1.0));
        // Constant to 1e-9 (round-off of a computed constant): 10% around it.
        let (lo, hi) = if hi - lo <= 1e-9 * lo.abs().max(hi.abs()) || hi - lo < f64::MIN_POSITIVE {
            let d = if lo.abs() > 0.0 { 0.1 * lo.abs() } else { 1.0 };
            (lo - d, hi + d)
        } else {
            (lo, hi)
        };
        // Halves, so that hi - lo cannot overflow.
        let w = hi / 2.0 - lo / 2.0;
        let r = (lo - 2.0 * pad_lo * w)..(hi + 2.0 * pad_hi * w);
        if r.start.is_finite() && r.end.is_finite() && r.start < r.end {
            r
        } else {
            lo..hi
        }
    }
}

fn bounds<'a>(values: impl Iterator<Item = &'a f64>) -> Option<(f64, f64)> {
    values.fold(None, |acc, &v| match acc {
        None => Some((v, v)),
        Some((lo, hi)) => Some((lo.min(v), hi.max(v))),
    })
}

/// How the ticks of a linear axis are labelled: all plain (0.25, 150) or,
/// for an axis whose largest tick is at least 1e5 or below 1e-3, all
/// scientific (2.5e-4), with enough digits to tell neighbours apart.
#[derive(Clone, Copy, Debug)]
struct TickFormat {
    step: f64,
    scientific: bool,
}

impl TickFormat {
    fn new(ticks: &[f64]) -> TickFormat {
        let step = ticks
            .windows(2)
            .map(|w| (w[1] - w[0]).abs())
            .filter(|d| *d > 0.0)
            .fold(f64::INFINITY, f64::min);
        let step = if step.is_finite() { step } else { 0.0 };
        let biggest = ticks.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        TickFormat {
            step,
            scientific: biggest >= 1e5 || (biggest > 0.0 && biggest < 1e-3),
        }
    }

    fn label(&self, v: f64) -> String {
        // A tick at zero computed as -1e-17 is 0, not "-0".
        if v == 0.0 || !v.is_finite() || v.abs() < 1e-9 * self.step {
            return "0".into();
        }
        let digits = |x: f64| x.abs().log10().floor();
        if self.scientific {
            let decimals = if self.step > 0.0 {
                (digits(v) - digits(self.step)).clamp(0.0, 12.0) as usize
            } else {
                2
            };
            let s = format!("{v:.decimals$e}");
            // 1.50e3 -> 1.5e3, 2.00e-4 -> 2e-4
            return match s.split_once('e') {
                Some((m, e)) if m.contains('.') => {
                    format!("{}e{e}", m.trim_end_matches('0').trim_end_matches('.'))
                }
                _ => s,
            };
        }
        let decimals = if self.step > 0.0 {
            (-digits(self.step)).clamp(0.0, 12.0) as usize
        } else {
            3
        };
        let s = format!("{v:.decimals$}");
        let s = if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            s
        };
        if s == "-0" {
            "0".into()
        } else {
            s
        }
    }
}

/// The range and the tick labels of a linear axis for data within
/// `bounds` (None: no data), as the plots draw a y axis (before any room is
/// made for the legend); with `from_zero` the range includes 0.
pub fn linear_axis(bounds: Option<(f64, f64)>, from_zero: bool) -> (Range<f64>, Vec<String>) {
    let range = y_axis_range(bounds, false, from_zero);
    let ticks = RangedCoordf64::from(range.clone()).key_points(BoldPoints(Y_TICKS));
    let format = TickFormat::new(&ticks);
    let labels = ticks.iter().map(|&v| format.label(v)).collect();
    (range, labels)
}

/// The y range of the data within `bounds`.
fn y_axis_range(bounds: Option<(f64, f64)>, log_y: bool, from_zero: bool) -> Range<f64> {
    let bounds = match bounds {
        Some((lo, hi)) if from_zero && !log_y => Some((lo.min(0.0), hi.max(0.0))),
        b => b,
    };
    axis_range(bounds, log_y, 0.04, 0.08)
}

/// Log-axis tick label: 1e-6, 0.01, 1, 100, 1e4 …
fn log_tick_label(v: f64) -> String {
    let e = v.log10();
    if (e - e.round()).abs() < 1e-6 {
        let e = e.round() as i32;
        return match e {
            -2..=-1 => format!("{:.*}", (-e) as usize, 10f64.powi(e)),
            0..=3 => format!("{}", 10i32.pow(e as u32)),
            _ => format!("1e{e}"),
        };
    }
    let s = format!("{v:.1e}");
    match s.split_once('e') {
        Some((m, e)) => format!("{}e{e}", m.trim_end_matches('0').trim_end_matches('.')),
        None => s,
    }
}

/// The x range a contact plot zooms on, for candidates at `x` (any order)
/// of which `in_contact` touch: the contact zone widened by half its extent
/// on each side (at least 2% of the surface's), and out to the nearest
/// candidate beyond each end, so that the pressure's fall to zero shows;
/// within the candidates' extent. None (the whole surface) when nothing
/// touches, or when the zoom would still show more than 70% of it.
pub fn contact_zoom(x: &[f64], in_contact: &[bool]) -> Option<Range<f64>> {
    let finite = || x.iter().copied().filter(|v| v.is_finite());
    let (lo, hi) = bounds(finite().collect::<Vec<_>>().iter())?;
    let touching = x
        .iter()
        .zip(in_contact)
        .filter(|(v, &c)| c && v.is_finite())
        .map(|(v, _)| v);
    let (c_lo, c_hi) = bounds(touching)?;
    let margin = (0.5 * (c_hi - c_lo)).max(0.02 * (hi - lo));
    let below = finite()
        .filter(|&v| v < c_lo)
        .fold(f64::NEG_INFINITY, f64::max);
    let above = finite().filter(|&v| v > c_hi).fold(f64::INFINITY, f64::min);
    let z_lo = (c_lo - margin).min(below).max(lo);
    let z_hi = (c_hi + margin).max(above).min(hi);
    (z_hi - z_lo <= 0.7 * (hi - lo)).then_some(z_lo..z_hi)
}

/// A line through points sorted by `x` becomes runs that do not join what
/// is not joined: a NaN (a break, see [`Series`]) goes between two
/// neighbours of different `group`s, and across a gap more than 4 times
/// the wider of the spacings on either side of it (a hole in the surface).
pub fn break_lines(x: &[f64], y: &[f64], group: &[usize]) -> (Vec<f64>, Vec<f64>) {
    let n = x.len().min(y.len());
    let dx: Vec<f64> = (1..n).map(|i| x[i] - x[i - 1]).collect();
    // The nearest positive spacing before and after each gap.
    let before = |j: usize| dx[..j].iter().rev().copied().find(|d| *d > 0.0);
    let after = |j: usize| dx[j + 1..].iter().copied().find(|d| *d > 0.0);
    let (mut bx, mut by) = (Vec::with_capacity(n + 4), Vec::with_capacity(n + 4));
    for i in 0..n {
        if i > 0 {
            let j = i - 1;
            let other_group = group.get(i) != group.get(j);
            let neighbours = match (before(j), after(j)) {
                (Some(a), Some(b)) => Some(a.max(b)),
                (a, b) => a.or(b),
            };
            let hole = neighbours.is_some_and(|h| dx[j] > 4.0 * h);
            if other_group || hole {
                bx.push(f64::NAN);
                by.push(f64::NAN);
            }
        }
        bx.push(x[i]);
        by.push(y[i]);
    }
    (bx, by)
}

/// Colours (the "tab10" palette), by series index.
const PALETTE: [RGBColor; 10] = [
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(255, 127, 14),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(127, 127, 127),
    RGBColor(188, 189, 34),
    RGBColor(23, 190, 207),
];

/// Chooses a legend corner where the legend covers the fewest data, given
/// the data in unit coordinates (0..1 across the plotting area, y up) and
/// the legend's size in the same units. Returns the position and whether
/// it covers data anyway.
fn legend_corner(unit: &[Vec<(f64, f64)>], w: f64, h: f64) -> (SeriesLabelPosition, usize) {
    // Samples along the runs, so that a line crossing a corner counts.
    let mut samples = Vec::new();
    for run in unit {
        if run.len() == 1 {
            samples.push(run[0]);
        }
        for p in run.windows(2) {
            for k in 0..=8 {
                let t = k as f64 / 8.0;
                samples.push((
                    p[0].0 + t * (p[1].0 - p[0].0),
                    p[0].1 + t * (p[1].1 - p[0].1),
                ));
            }
        }
    }
    let count = |x0: f64, y0: f64| {
        samples
            .iter()
            .filter(|&&(x, y)| x >= x0 && x <= x0 + w && y >= y0 && y <= y0 + h)
            .count()
    };
    let candidates = [
        (SeriesLabelPosition::UpperRight, 1.0 - w, 1.0 - h),
        (SeriesLabelPosition::UpperLeft, 0.0, 1.0 - h),
        (SeriesLabelPosition::LowerRight, 1.0 - w, 0.0),
        (SeriesLabelPosition::LowerLeft, 0.0, 0.0),
        (SeriesLabelPosition::UpperMiddle, 0.5 - w / 2.0, 1.0 - h),
    ];
    let mut best = (SeriesLabelPosition::UpperRight, usize::MAX);
    for (pos, x0, y0) in candidates {
        let c = count(x0, y0);
        if c < best.1 {
            best = (pos, c);
        }
    }
    best
}

/// Renders the plot to PNG bytes.
fn render(
    title: &str,
    x_label: &str,
    y_label: &str,
    series: &[Series],
    log_y: bool,
    axes: &Axes,
) -> Result<Vec<u8>, String> {
    let font = load_font()?;
    // plotters may panic on corner cases it does not expect; a plot is never
    // worth aborting the solver for.
    let drawn = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        let mut buf = vec![255u8; (WIDTH * HEIGHT * 3) as usize];
        {
            let canvas = Canvas {
                inner: BitMapBackend::with_buffer(&mut buf, (WIDTH, HEIGHT)),
                font,
            };
            let root = canvas.into_drawing_area();
            draw(&root, font, title, x_label, y_label, series, log_y, axes)?;
            root.present().map_err(|e| e.to_string())?;
        }
        Ok::<_, String>(buf)
    }))
    .map_err(|_| "the plotting library panicked".to_string())??;
    encode_png(&drawn, WIDTH, HEIGHT)
}

#[allow(clippy::too_many_arguments)]
fn draw(
    root: &DrawingArea<Canvas, Shift>,
    font: &FontRef<'static>,
    title: &str,
    x_label: &str,
    y_label: &str,
    series: &[Series],
    log_y: bool,
    axes: &Axes,
) -> Result<(), String> {
    let e = |e: DrawingAreaErrorKind<_>| e.to_string();
    root.fill(&WHITE).map_err(e)?;

    // A given x range, padded as the data's would be; the data cut to it.
    let given_x = axes
        .x_range
        .as_ref()
        .filter(|r| r.start.is_finite() && r.end.is_finite() && r.start <= r.end)
        .map(|r| axis_range(Some((r.start, r.end)), false, 0.02, 0.02));
    let prepare = |floor: f64| -> Vec<Clean> {
        series
            .iter()
            .map(|s| {
                let c = clean(s, log_y, floor);
                match &given_x {
                    Some(r) => clip_x(c, r, matches!(s.style, Style::Line | Style::DashedLine)),
                    None => c,
                }
            })
            .collect()
    };
    let mut cleaned = prepare(0.0);
    if log_y {
        // Keep at most MAX_DECADES below the largest value.
        let points = cleaned.iter().flat_map(|c| c.runs.iter().flatten());
        if let Some((lo, hi)) = bounds(points.map(|p| &p.1)) {
            if hi.log10() - lo.log10() > MAX_DECADES {
                cleaned = prepare(hi / 10f64.powf(MAX_DECADES));
            }
        }
    }
    let all = || cleaned.iter().flat_map(|c| c.runs.iter().flatten());
    let has_data = all().next().is_some();
    let xb = bounds(all().map(|p| &p.0));
    let yb = bounds(all().map(|p| &p.1));
    let x_range = given_x.unwrap_or_else(|| axis_range(xb, false, 0.02, 0.02));
    let mut y_range = y_axis_range(yb, log_y, axes.y_from_zero);

    // Legend size in unit coordinates of the plotting area (estimated).
    let labelled: Vec<usize> = (0..series.len())
        .filter(|&i| !series[i].label.is_empty())
        .collect();
    let plot_w = f64::from(WIDTH) - 150.0;
    let plot_h = f64::from(HEIGHT) - 170.0;
    let longest = labelled
        .iter()
        .map(|&i| series[i].label.chars().count())
        .max()
        .unwrap_or(0) as f64;
    let legend_w = (longest * f64::from(LEGEND_SIZE) * 0.55 + 80.0) / plot_w;
    let legend_h = (labelled.len() as f64 * (f64::from(LEGEND_SIZE) + 10.0) + 30.0) / plot_h;
    let to_unit = |y_range: &Range<f64>| -> Vec<Vec<(f64, f64)>> {
        let fy = |y: f64| {
            if log_y {
                (y.log10() - y_range.start.log10()) / (y_range.end.log10() - y_range.start.log10())
            } else {
                (y - y_range.start) / (y_range.end - y_range.start)
            }
        };
        let fx = |x: f64| (x - x_range.start) / (x_range.end - x_range.start);
        cleaned
            .iter()
            .flat_map(|c| c.runs.iter())
            .map(|r| r.iter().map(|&(x, y)| (fx(x), fy(y))).collect())
            .collect()
    };
    let (mut position, covered) = legend_corner(&to_unit(&y_range), legend_w, legend_h);
    if covered > 0 && !labelled.is_empty() && legend_h < 0.6 {
        // Every corner covers data: raise the top of the y axis so that the
        // data stay below the legend, and put the legend upper right.
        let grow = legend_h / (1.0 - legend_h);
        if log_y {
            let (lo, hi) = (y_range.start.log10(), y_range.end.log10());
            y_range.end = 10f64.powf(hi + grow * (hi - lo));
        } else {
            y_range.end += grow * (y_range.end - y_range.start);
        }
        position = SeriesLabelPosition::UpperRight;
    }

    // The tick labels plotters will draw, to size the y label area to them.
    let x_ticks = RangedCoordf64::from(x_range.clone()).key_points(BoldPoints(X_TICKS));
    let y_ticks = if log_y {
        let c: LogCoord<f64> = y_range.clone().log_scale().into();
        c.key_points(BoldPoints(Y_TICKS))
    } else {
        RangedCoordf64::from(y_range.clone()).key_points(BoldPoints(Y_TICKS))
    };
    let x_format = TickFormat::new(&x_ticks);
    let y_format = TickFormat::new(&y_ticks);
    let y_tick_label = |v: f64| {
        if log_y {
            log_tick_label(v)
        } else {
            y_format.label(v)
        }
    };
    let widest_tick = y_ticks
        .iter()
        .map(|&v| text_width(font, f64::from(TICK_SIZE), &y_tick_label(v)))
        .fold(0.0, f64::max);

    let mut builder = ChartBuilder::on(root);
    builder
        .caption(title, (FAMILY, fit(font, title, TITLE_SIZE, WIDTH - 60)))
        .margin(20)
        .margin_right(40)
        .x_label_area_size(75);
    let label_size = fit(font, x_label, LABEL_SIZE, WIDTH - 220).min(fit(
        font,
        y_label,
        LABEL_SIZE,
        HEIGHT - 200,
    ));
    // Tick labels, their gap to the axis, the (rotated) y label and a gap.
    let y_area = widest_tick.ceil() as u32
        + 12
        + if y_label.is_empty() {
            0
        } else {
            label_size + 18
        };
    builder.y_label_area_size(y_area.clamp(40, WIDTH / 3));

    if log_y {
        let mut chart = builder
            .build_cartesian_2d(x_range.clone(), y_range.clone().log_scale())
            .map_err(e)?;
        chart
            .configure_mesh()
            .x_desc(x_label)
            .y_desc(y_label)
            .axis_desc_style((FAMILY, label_size))
            .label_style((FAMILY, TICK_SIZE))
            .x_labels(X_TICKS)
            .y_labels(Y_TICKS)
            .x_label_formatter(&|v| x_format.label(*v))
            .y_label_formatter(&|v| y_tick_label(*v))
            .light_line_style(RGBColor(235, 235, 235))
            .bold_line_style(RGBColor(210, 210, 210))
            .draw()
            .map_err(e)?;
        draw_series(&mut chart, series, &cleaned)?;
        finish(&mut chart, position, &labelled, has_data)
    } else {
        let mut chart = builder
            .build_cartesian_2d(x_range.clone(), y_range.clone())
            .map_err(e)?;
        chart
            .configure_mesh()
            .x_desc(x_label)
            .y_desc(y_label)
            .axis_desc_style((FAMILY, label_size))
            .label_style((FAMILY, TICK_SIZE))
            .x_labels(X_TICKS)
            .y_labels(Y_TICKS)
            .x_label_formatter(&|v| x_format.label(*v))
            .y_label_formatter(&|v| y_tick_label(*v))
            .light_line_style(RGBColor(235, 235, 235))
            .bold_line_style(RGBColor(210, 210, 210))
            .draw()
            .map_err(e)?;
        draw_series(&mut chart, series, &cleaned)?;
        finish(&mut chart, position, &labelled, has_data)
    }
}

/// Draws every series and registers its legend entry.
fn draw_series<'a, X, Y>(
    chart: &mut ChartContext<'a, Canvas<'a>, Cartesian2d<X, Y>>,
    series: &[Series],
    cleaned: &[Clean],
) -> Result<(), String>
where
    X: Ranged<ValueType = f64>,
    Y: Ranged<ValueType = f64>,
{
    let e = |e: DrawingAreaErrorKind<_>| e.to_string();
    for (i, (s, c)) in series.iter().zip(cleaned).enumerate() {
        let color = PALETTE[i % PALETTE.len()];
        let line = ShapeStyle {
            color: color.to_rgba(),
            filled: false,
            stroke_width: 3,
        };
        let fill = color.filled();
        let points = || c.runs.iter().flatten().map(|&p| Circle::new(p, 4, fill));
        let ring = ShapeStyle {
            color: color.to_rgba(),
            filled: false,
            stroke_width: 2,
        };
        let rings = || {
            c.runs
                .iter()
                .flatten()
                .map(move |&p| Circle::new(p, 6, ring))
        };
        // A line through one point (or one repeated point) would not
        // show: mark it.
        let is_dot = |r: &Vec<(f64, f64)>| r.iter().all(|p| *p == r[0]);
        let lone = || {
            c.runs
                .iter()
                .filter(|r| is_dot(r))
                .map(|r| Circle::new(r[0], 4, fill))
        };
        let anno = match s.style {
            Style::Points => chart.draw_series(points()).map_err(e)?,
            Style::Rings => chart.draw_series(rings()).map_err(e)?,
            Style::Line => {
                chart.draw_series(lone()).map_err(e)?;
                chart
                    .draw_series(
                        c.runs
                            .iter()
                            .filter(|r| !is_dot(r))
                            .map(|r| PathElement::new(r.clone(), line)),
                    )
                    .map_err(e)?
            }
            Style::DashedLine => {
                chart.draw_series(lone()).map_err(e)?;
                chart
                    .draw_series(
                        c.runs
                            .iter()
                            .filter(|r| !is_dot(r))
                            .map(|r| DashedPathElement::new(r.clone(), 12, 7, line)),
                    )
                    .map_err(e)?
            }
        };
        if s.label.is_empty() {
            continue;
        }
        anno.label(s.label);
        match s.style {
            Style::Points => {
                anno.legend(move |(x, y)| Circle::new((x + 15, y), 5, fill));
            }
            Style::Rings => {
                anno.legend(move |(x, y)| Circle::new((x + 15, y), 6, ring));
            }
            Style::Line => {
                anno.legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 30, y)], line));
            }
            Style::DashedLine => {
                anno.legend(move |(x, y)| {
                    DashedPathElement::new(vec![(x, y), (x + 30, y)], 9, 5, line)
                });
            }
        }
    }
    Ok(())
}

/// Draws the legend (if any series is labelled) and the "no data" note.
fn finish<'a, X, Y>(
    chart: &mut ChartContext<'a, Canvas<'a>, Cartesian2d<X, Y>>,
    position: SeriesLabelPosition,
    labelled: &[usize],
    has_data: bool,
) -> Result<(), String>
where
    X: Ranged<ValueType = f64>,
    Y: Ranged<ValueType = f64>,
{
    let e = |e: DrawingAreaErrorKind<_>| e.to_string();
    if !labelled.is_empty() {
        chart
            .configure_series_labels()
            .position(position)
            .margin(15)
            .legend_area_size(40)
            .label_font((FAMILY, LEGEND_SIZE))
            .background_style(WHITE.mix(0.9))
            .border_style(RGBColor(160, 160, 160))
            .draw()
            .map_err(e)?;
    }
    if !has_data {
        let area = chart.plotting_area().strip_coord_spec();
        let (w, h) = area.dim_in_pixel();
        let style = TextStyle::from((FAMILY, LABEL_SIZE).into_font())
            .color(&RGBColor(120, 120, 120))
            .pos(text_anchor::Pos::new(
                text_anchor::HPos::Center,
                text_anchor::VPos::Center,
            ));
        area.draw(&Text::new("no data", (w as i32 / 2, h as i32 / 2), style))
            .map_err(e)?;
    }
    Ok(())
}

/// The largest font size, at most `size`, at which `text` is at most
/// `width` pixels wide (never below 10).
fn fit(font: &FontRef<'static>, text: &str, size: u32, width: u32) -> u32 {
    let mut s = size;
    while s > 10 && text_width(font, f64::from(s), text) > f64::from(width) {
        s -= 1;
    }
    s
}

/// Width in pixels of `text` at `size`.
fn text_width(font: &FontRef<'static>, size: f64, text: &str) -> f64 {
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
/// renderer drops each glyph's side bearing, which gives uneven letter
/// spacing; here glyphs are placed at their outline bounds.) Layout and
/// drawing share one measure, so labels sit where plotters expects them.
struct Canvas<'a> {
    inner: BitMapBackend<'a>,
    font: &'static FontRef<'static>,
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

fn encode_png(rgb: &[u8], width: u32, height: u32) -> Result<Vec<u8>, String> {
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
fn font_candidates() -> Vec<PathBuf> {
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
fn load_font() -> Result<&'static FontRef<'static>, String> {
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
fn read_font(candidates: &[PathBuf]) -> Result<(&'static [u8], FontRef<'static>), String> {
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

#[cfg(test)]
mod tests {
    use super::*;

    fn temp_dir(tag: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("ubr-plot-{tag}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).expect("create a temporary directory");
        dir
    }

    /// Decodes a PNG file: (width, height, RGB bytes).
    fn decode(path: &Path) -> (u32, u32, Vec<u8>) {
        let bytes = std::fs::read(path).expect("the PNG exists");
        assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n", "PNG signature");
        let mut reader = png::Decoder::new(std::io::Cursor::new(bytes))
            .read_info()
            .expect("a valid PNG header");
        let mut buf = vec![0; reader.output_buffer_size().expect("a size")];
        let info = reader.next_frame(&mut buf).expect("valid PNG data");
        assert_eq!(info.color_type, png::ColorType::Rgb);
        buf.truncate(info.buffer_size());
        (info.width, info.height, buf)
    }

    /// Number of pixels that are neither white nor grey (i.e. coloured).
    fn coloured_pixels(rgb: &[u8]) -> usize {
        rgb.chunks(3)
            .filter(|p| {
                let (mx, mn) = (p.iter().max(), p.iter().min());
                matches!((mx, mn), (Some(a), Some(b)) if a - b > 60)
            })
            .count()
    }

    fn dark_pixels(rgb: &[u8]) -> usize {
        rgb.chunks(3).filter(|p| p.iter().all(|&c| c < 100)).count()
    }

    /// The contact plot of the examples: computed pressure, Hertz curve,
    /// scattered nodal values and a friction pair.
    fn contact_example(path: &Path) -> Result<(), String> {
        let b = 1.2;
        let p0 = 150.0;
        let hertz = |x: f64| {
            if x.abs() < b {
                p0 * (1.0 - (x / b).powi(2)).sqrt()
            } else {
                0.0
            }
        };
        let xs: Vec<f64> = (0..=400).map(|i| -2.0 + 4.0 * i as f64 / 400.0).collect();
        let ph: Vec<f64> = xs.iter().map(|&x| hertz(x)).collect();
        let xn: Vec<f64> = (0..=40).map(|i| -2.0 + 4.0 * i as f64 / 40.0).collect();
        let pn: Vec<f64> = xn
            .iter()
            .enumerate()
            .map(|(i, &x)| (hertz(x) * (1.0 + 0.04 * ((i * 7 % 5) as f64 - 2.0))).max(0.0))
            .collect();
        let tn: Vec<f64> = xn
            .iter()
            .zip(&pn)
            .map(|(&x, &p)| (0.3 * p).min(40.0 * x.abs()))
            .collect();
        let bound: Vec<f64> = pn.iter().map(|p| 0.3 * p).collect();
        let scatter: Vec<f64> = pn.iter().map(|p| p * 1.02 + 3.0).collect();
        plot_lines(
            path,
            "Contact pressure along the surface",
            "position along the surface x",
            "traction",
            &[
                Series {
                    label: "pressure λn",
                    x: &xn,
                    y: &pn,
                    style: Style::Line,
                },
                Series {
                    label: "Hertz",
                    x: &xs,
                    y: &ph,
                    style: Style::DashedLine,
                },
                Series {
                    label: "nodal pressure (other rank)",
                    x: &xn,
                    y: &scatter,
                    style: Style::Points,
                },
                Series {
                    label: "|tangential traction|",
                    x: &xn,
                    y: &tn,
                    style: Style::Line,
                },
                Series {
                    label: "friction bound μ λn",
                    x: &xn,
                    y: &bound,
                    style: Style::DashedLine,
                },
            ],
            false,
        )
    }

    fn history_example(path: &Path) -> Result<(), String> {
        let it: Vec<f64> = (0..60).map(f64::from).collect();
        let r1: Vec<f64> = it
            .iter()
            .map(|&k| 0.8f64.powf(k) * (1.0 + 0.3 * (k * 0.7).sin()))
            .collect();
        let r2: Vec<f64> = it.iter().map(|&k| 3e-1 * 0.6f64.powf(k)).collect();
        // A zero and a negative value on the log axis are dropped.
        let mut r3: Vec<f64> = it.iter().map(|&k| 1e-2 * 0.85f64.powf(k)).collect();
        r3[10] = 0.0;
        r3[20] = -1.0;
        r3[30] = f64::NAN;
        plot_history(
            path,
            "Uzawa block relaxation: convergence",
            &it,
            &[
                ("displacement change", &r1),
                ("multiplier change", &r2),
                ("complementarity", &r3),
            ],
        )
    }

    #[test]
    fn contact_plot_is_a_nonblank_png() {
        let dir = temp_dir("contact");
        let path = dir.join("contact.png");
        contact_example(&path).expect("plot");
        let (w, h, rgb) = decode(&path);
        assert_eq!((w, h), (WIDTH, HEIGHT));
        assert!(coloured_pixels(&rgb) > 5000, "curves are drawn");
        assert!(dark_pixels(&rgb) > 2000, "text and axes are drawn");
        // Only the plot: no temporary file left behind.
        assert_eq!(std::fs::read_dir(&dir).map(|d| d.count()).ok(), Some(1));
        if let Ok(out) = std::env::var("UBR_PLOT_EXAMPLES") {
            let out = PathBuf::from(out);
            let _ = std::fs::create_dir_all(&out);
            contact_example(&out.join("contact.png")).expect("example plot");
        }
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn history_plot_is_a_nonblank_png() {
        let dir = temp_dir("history");
        let path = dir.join("history.png");
        history_example(&path).expect("plot");
        let (w, h, rgb) = decode(&path);
        assert_eq!((w, h), (WIDTH, HEIGHT));
        assert!(coloured_pixels(&rgb) > 3000, "curves are drawn");
        assert!(dark_pixels(&rgb) > 2000, "text and axes are drawn");
        if let Ok(out) = std::env::var("UBR_PLOT_EXAMPLES") {
            let out = PathBuf::from(out);
            let _ = std::fs::create_dir_all(&out);
            history_example(&out.join("history.png")).expect("example plot");
        }
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn degenerate_data_never_panics() {
        let dir = temp_dir("degenerate");
        let nan = [f64::NAN, f64::INFINITY, f64::NEG_INFINITY];
        let cases: Vec<(&str, Vec<Series>, bool)> = vec![
            ("none", vec![], false),
            ("none_log", vec![], true),
            (
                "empty",
                vec![Series {
                    label: "empty",
                    x: &[],
                    y: &[],
                    style: Style::Line,
                }],
                true,
            ),
            (
                "nonfinite",
                vec![Series {
                    label: "nan",
                    x: &[0.0, 1.0, 2.0],
                    y: &nan,
                    style: Style::DashedLine,
                }],
                false,
            ),
            (
                "nonpositive_log",
                vec![Series {
                    label: "zeros",
                    x: &[0.0, 1.0, 2.0],
                    y: &[0.0, -1.0, 0.0],
                    style: Style::Points,
                }],
                true,
            ),
            (
                "single",
                vec![Series {
                    label: "",
                    x: &[3.0],
                    y: &[3.0],
                    style: Style::Line,
                }],
                false,
            ),
            (
                "constant_log",
                vec![Series {
                    label: "const",
                    x: &[1.0, 1.0],
                    y: &[1e-300, 1e-300],
                    style: Style::Line,
                }],
                true,
            ),
            (
                "huge",
                vec![Series {
                    label: "huge",
                    x: &[-f64::MAX, f64::MAX],
                    y: &[f64::MAX, -f64::MAX],
                    style: Style::Line,
                }],
                false,
            ),
            (
                "large",
                vec![Series {
                    label: "large",
                    x: &[-1e300, 1e300],
                    y: &[1e300, -1e300],
                    style: Style::Points,
                }],
                false,
            ),
            (
                "wide_log",
                vec![Series {
                    label: "600 decades",
                    x: &[0.0, 1.0, 2.0, 3.0],
                    y: &[1e300, 1.0, 1e-300, 5e-324],
                    style: Style::Line,
                }],
                true,
            ),
            (
                "tiny",
                vec![Series {
                    label: "tiny",
                    x: &[0.0, 1e-310, 2e-310],
                    y: &[1.0, 1.0 + 1e-15, 1.0],
                    style: Style::Line,
                }],
                false,
            ),
            (
                "mismatched",
                vec![Series {
                    label: "mismatched lengths",
                    x: &[0.0, 1.0, 2.0, 3.0],
                    y: &[1.0, 2.0],
                    style: Style::Points,
                }],
                false,
            ),
        ];
        for (name, series, log_y) in cases {
            let path = dir.join(format!("{name}.png"));
            plot_lines(&path, name, "x", "y", &series, log_y)
                .unwrap_or_else(|e| panic!("case {name}: {e}"));
            let (w, _, rgb) = decode(&path);
            assert_eq!(w, WIDTH);
            assert!(dark_pixels(&rgb) > 500, "case {name}: axes are drawn");
        }
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn failed_write_names_the_file_and_leaves_nothing() {
        let dir = temp_dir("fail");
        let path = dir.join("missing/plot.png");
        let e = plot_history(&path, "t", &[0.0, 1.0], &[("r", &[1.0, 0.1])])
            .expect_err("missing directory");
        assert!(e.contains("plot.png"), "{e}");
        assert_eq!(std::fs::read_dir(&dir).map(|d| d.count()).ok(), Some(0));
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn missing_font_is_a_clear_error() {
        let dir = temp_dir("font");
        let not_a_font = dir.join("fake.ttf");
        std::fs::write(&not_a_font, b"not a font").expect("write");
        let e = read_font(&[dir.join("missing.ttf"), not_a_font]).expect_err("no usable font");
        assert!(e.contains("fonts-dejavu-core"), "{e}");
        assert!(
            e.contains("missing.ttf") && e.contains("not a usable font"),
            "{e}"
        );
        let _ = std::fs::remove_dir_all(&dir);
    }

    /// The lowest row with a coloured pixel in a PNG file.
    fn lowest_coloured_row(path: &Path) -> usize {
        let (w, _, rgb) = decode(path);
        rgb.chunks(3)
            .enumerate()
            .filter(|(_, p)| {
                let (mx, mn) = (p.iter().max(), p.iter().min());
                matches!((mx, mn), (Some(a), Some(b)) if a - b > 60)
            })
            .map(|(i, _)| i / w as usize)
            .max()
            .unwrap_or(0)
    }

    /// A line that turns back sharply (a zig-zag through scattered nodes)
    /// stays where its points are: no spike below its lowest value, past
    /// the axis (the bitmap backend's joins of nearly parallel legs reached
    /// 100 px below it, into the tick labels).
    #[test]
    fn sharp_turns_do_not_spike() {
        let dir = temp_dir("spike");
        // Nodes 2 px apart, alternately at 0 and 1: the legs of each turn
        // nearly parallel (the bound s at scattered 3D nodes).
        // Scattered nodes (a 3D bound against the distance): close in x,
        // scattered in y, the legs of each turn nearly parallel.
        let mut seed = 12345u64;
        let mut next = || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        let mut x: Vec<f64> = (0..300).map(|_| 0.6 * next()).collect();
        x.sort_by(f64::total_cmp);
        let mut y: Vec<f64> = x
            .iter()
            .map(|&v| (40.0 * (1.0 - v / 0.6) + 10.0 * (next() - 0.5)).max(0.0))
            .collect();
        x.extend([1.0, 3.0]);
        y.extend([0.0, 0.0]);
        let mut lowest = Vec::new();
        for (name, style) in [("points", Style::Points), ("line", Style::Line)] {
            let path = dir.join(format!("{name}.png"));
            let series = [Series {
                label: "",
                x: &x,
                y: &y,
                style,
            }];
            plot_lines(&path, name, "x", "y", &series, false).expect("plot");
            lowest.push(lowest_coloured_row(&path));
        }
        // A dot reaches 4 px below its centre, a 3 px line 1-2 px.
        assert!(
            lowest[1] <= lowest[0],
            "line {} vs points {}",
            lowest[1],
            lowest[0]
        );
        let _ = std::fs::remove_dir_all(&dir);
    }

    /// A given x range cuts lines at its border and drops points outside.
    #[test]
    fn clipping_to_an_x_range() {
        let c = Clean {
            runs: vec![vec![(0.0, 0.0), (2.0, 2.0), (4.0, 0.0), (6.0, 2.0)]],
        };
        let line = clip_x(
            Clean {
                runs: c.runs.clone(),
            },
            &(1.0..5.0),
            true,
        );
        assert_eq!(
            line.runs,
            vec![vec![(1.0, 1.0), (2.0, 2.0), (4.0, 0.0), (5.0, 1.0)]]
        );
        let points = clip_x(c, &(1.0..5.0), false);
        assert_eq!(points.runs, vec![vec![(2.0, 2.0), (4.0, 0.0)]]);
        // A segment across the whole range, and one that leaves and comes back.
        let across = Clean {
            runs: vec![vec![(0.0, 0.0), (10.0, 10.0)]],
        };
        assert_eq!(
            clip_x(across, &(2.0..3.0), true).runs,
            vec![vec![(2.0, 2.0), (3.0, 3.0)]]
        );
        let back = Clean {
            runs: vec![vec![(0.0, 0.0), (2.0, 0.0), (0.0, 1.0)]],
        };
        assert_eq!(
            clip_x(back, &(-1.0..1.0), true).runs,
            vec![vec![(0.0, 0.0), (1.0, 0.0)], vec![(1.0, 0.5), (0.0, 1.0)]]
        );
    }

    #[test]
    fn tick_labels_are_short() {
        let f = TickFormat::new(&[0.0, 0.5, 1.0]);
        assert_eq!(f.label(0.0), "0");
        assert_eq!(f.label(0.5), "0.5");
        let f = TickFormat::new(&[100.0, 150.0, 200.0]);
        assert_eq!(f.label(150.0), "150");
        let f = TickFormat::new(&[0.0, 5e-4, 1e-3, 1.5e-3]);
        assert_eq!(f.label(5e-4), "0.0005");
        assert_eq!(f.label(1.5e-3), "0.0015");
        let f = TickFormat::new(&[0.0, 1e-4, 2e-4]);
        assert_eq!(f.label(2e-4), "2e-4");
        let f = TickFormat::new(&[1.4e6, 1.5e6]);
        assert_eq!(f.label(1.5e6), "1.5e6");
        // Neighbours stay distinct with a fine step.
        let f = TickFormat::new(&[-1.2345e-7, -1.2344e-7]);
        assert_ne!(f.label(-1.2345e-7), f.label(-1.2344e-7));
        assert_eq!(log_tick_label(1e-6), "1e-6");
        assert_eq!(log_tick_label(0.01), "0.01");
        assert_eq!(log_tick_label(1.0), "1");
        assert_eq!(log_tick_label(1000.0), "1000");
        assert_eq!(log_tick_label(1e4), "1e4");
        assert_eq!(log_tick_label(3e-5), "3e-5");
    }
}
