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

mod axes;
mod canvas;

use super::write_atomic;
use ab_glyph::FontRef;
use axes::{
    axis_range, bounds, clean, clip_x, log_tick_label, y_axis_range, Clean, TickFormat, MAX_DECADES,
};
pub use axes::{break_lines, contact_zoom, linear_axis};
use canvas::{encode_png, fit, load_font, text_width, Canvas};
use plotters::coord::combinators::LogCoord;
use plotters::coord::ranged1d::BoldPoints;
use plotters::coord::types::RangedCoordf64;
use plotters::coord::Shift;
use plotters::element::DashedPathElement;
use plotters::prelude::*;
use plotters::style::text_anchor;
use std::ops::Range;
use std::path::Path;

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

/// What a plot shows, decided before anything is drawn.
struct Layout {
    /// The series cut to what can be drawn.
    cleaned: Vec<Clean>,
    has_data: bool,
    x_range: Range<f64>,
    y_range: Range<f64>,
    /// The series with a legend entry.
    labelled: Vec<usize>,
    /// Where the legend goes.
    position: SeriesLabelPosition,
}

/// The data cut to what can be drawn, the axis ranges, and a legend corner
/// that covers no data (the y axis raised to make room when every corner
/// would).
fn layout(series: &[Series], log_y: bool, axes: &Axes) -> Layout {
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
    Layout {
        cleaned,
        has_data,
        x_range,
        y_range,
        labelled,
        position,
    }
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

    let Layout {
        cleaned,
        has_data,
        x_range,
        y_range,
        labelled,
        position,
    } = layout(series, log_y, axes);

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

#[cfg(test)]
mod tests;
