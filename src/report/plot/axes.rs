//! What a plot's axes show: the data cut to what can be drawn, the axis
//! ranges and the tick labels, the contact zoom and the broken lines.

use super::{Series, Y_TICKS};
use plotters::coord::ranged1d::BoldPoints;
use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;
use std::ops::Range;

/// A series after dropping the points that cannot be drawn: runs of
/// consecutive drawable points.
#[derive(Clone, Debug)]
pub(super) struct Clean {
    pub(super) runs: Vec<Vec<(f64, f64)>>,
}

/// `c` cut to `x` in `range`: points outside dropped; with `line`, each
/// segment cut at the border (a run that leaves the range ends there).
pub(super) fn clip_x(c: Clean, range: &Range<f64>, line: bool) -> Clean {
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
pub(super) const MAX_DECADES: f64 = 250.0;

/// Drops the points that cannot be drawn: non-finite or beyond [`MAX_ABS`];
/// with `log_y`, y values not above `floor` (at least 0).
pub(super) fn clean(s: &Series, log_y: bool, floor: f64) -> Clean {
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
pub(super) fn axis_range(
    bounds: Option<(f64, f64)>,
    log: bool,
    pad_lo: f64,
    pad_hi: f64,
) -> Range<f64> {
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

pub(super) fn bounds<'a>(values: impl Iterator<Item = &'a f64>) -> Option<(f64, f64)> {
    values.fold(None, |acc, &v| match acc {
        None => Some((v, v)),
        Some((lo, hi)) => Some((lo.min(v), hi.max(v))),
    })
}

/// How the ticks of a linear axis are labelled: all plain (0.25, 150) or,
/// for an axis whose largest tick is at least 1e5 or below 1e-3, all
/// scientific (2.5e-4), with enough digits to tell neighbours apart.
#[derive(Clone, Copy, Debug)]
pub(super) struct TickFormat {
    step: f64,
    scientific: bool,
}

impl TickFormat {
    pub(super) fn new(ticks: &[f64]) -> TickFormat {
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

    pub(super) fn label(&self, v: f64) -> String {
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
pub(super) fn y_axis_range(bounds: Option<(f64, f64)>, log_y: bool, from_zero: bool) -> Range<f64> {
    let bounds = match bounds {
        Some((lo, hi)) if from_zero && !log_y => Some((lo.min(0.0), hi.max(0.0))),
        b => b,
    };
    axis_range(bounds, log_y, 0.04, 0.08)
}

/// Log-axis tick label: 1e-6, 0.01, 1, 100, 1e4 …
pub(super) fn log_tick_label(v: f64) -> String {
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
