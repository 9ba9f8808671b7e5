//! Draws the benchmark figures of `bench/run` from a JSON spec, with the
//! crate's own plotting module (`ubr_petsc::report::plot`).
//!
//! Usage: `cargo run --release --example bench_plot -- SPEC.json`
//!
//! The spec is one plot or a list of plots:
//!
//! ```json
//! [{"path": "bench/results/fig2.png", "title": "...", "x_label": "...",
//!   "y_label": "...", "log_x": true, "log_y": true,
//!   "series": [{"label": "2D", "x": [0.01, 0.1], "y": [120, 40],
//!               "style": "line", "color": 0}]}]
//! ```
//!
//! `style` is `line` (default), `dashed` or `points`. `color` (optional) is
//! an index into the plotting module's 10-colour palette: the module colours
//! a series by its position, so empty, unlabelled series are inserted before
//! it until its position has that colour (several series can then share a
//! colour, e.g. one mesh drawn with a line for one method and dashes for
//! another). `plot.rs` has a logarithmic y axis only: with `log_x` the x
//! values are replaced by their base-10 logarithm (non-positive values are
//! dropped), and the x label should say so (e.g. "log10(r/E)").
use serde_json::Value;
use std::path::Path;
use ubr_petsc::report::plot::{plot_lines, Series, Style};

const PALETTE_LEN: usize = 10;

struct Owned {
    label: String,
    x: Vec<f64>,
    y: Vec<f64>,
    style: Style,
}

fn numbers(v: &Value, what: &str) -> Result<Vec<f64>, String> {
    v.as_array()
        .ok_or_else(|| format!("{what}: not an array"))?
        .iter()
        .map(|e| match e {
            Value::Null => Ok(f64::NAN),
            _ => e
                .as_f64()
                .ok_or_else(|| format!("{what}: not a number: {e}")),
        })
        .collect()
}

fn text(v: &Value, key: &str) -> String {
    v.get(key).and_then(Value::as_str).unwrap_or("").to_string()
}

fn flag(v: &Value, key: &str) -> bool {
    v.get(key).and_then(Value::as_bool).unwrap_or(false)
}

fn draw(p: &Value) -> Result<String, String> {
    let path = p
        .get("path")
        .and_then(Value::as_str)
        .ok_or("a plot without \"path\"")?;
    let log_x = flag(p, "log_x");
    let mut owned: Vec<Owned> = Vec::new();
    let empty = || Owned {
        label: String::new(),
        x: Vec::new(),
        y: Vec::new(),
        style: Style::Line,
    };
    let series = p
        .get("series")
        .and_then(Value::as_array)
        .ok_or_else(|| format!("{path}: no \"series\" list"))?;
    for (i, s) in series.iter().enumerate() {
        let what = format!("{path}: series {i}");
        let mut x = numbers(s.get("x").unwrap_or(&Value::Null), &format!("{what} x"))?;
        let y = numbers(s.get("y").unwrap_or(&Value::Null), &format!("{what} y"))?;
        if log_x {
            x = x
                .iter()
                .map(|&v| if v > 0.0 { v.log10() } else { f64::NAN })
                .collect();
        }
        let style = match s.get("style").and_then(Value::as_str).unwrap_or("line") {
            "line" => Style::Line,
            "dashed" => Style::DashedLine,
            "points" => Style::Points,
            other => return Err(format!("{what}: unknown style '{other}'")),
        };
        if let Some(c) = s.get("color").and_then(Value::as_u64) {
            while owned.len() % PALETTE_LEN != c as usize % PALETTE_LEN {
                owned.push(empty());
            }
        }
        owned.push(Owned {
            label: text(s, "label"),
            x,
            y,
            style,
        });
    }
    let borrowed: Vec<Series> = owned
        .iter()
        .map(|o| Series {
            label: &o.label,
            x: &o.x,
            y: &o.y,
            style: o.style,
        })
        .collect();
    plot_lines(
        Path::new(path),
        &text(p, "title"),
        &text(p, "x_label"),
        &text(p, "y_label"),
        &borrowed,
        flag(p, "log_y"),
    )?;
    Ok(path.to_string())
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if args.is_empty() {
        eprintln!("usage: bench_plot SPEC.json [SPEC.json ...]");
        std::process::exit(2);
    }
    let mut failed = false;
    for spec in &args {
        let parsed = std::fs::read_to_string(spec)
            .map_err(|e| format!("{spec}: {e}"))
            .and_then(|t| serde_json::from_str::<Value>(&t).map_err(|e| format!("{spec}: {e}")));
        let plots = match parsed {
            Ok(Value::Array(v)) => v,
            Ok(v) => vec![v],
            Err(e) => {
                eprintln!("bench_plot: {e}");
                failed = true;
                continue;
            }
        };
        for p in &plots {
            match draw(p) {
                Ok(path) => println!("plotted {path}"),
                Err(e) => {
                    eprintln!("bench_plot: {e}");
                    failed = true;
                }
            }
        }
    }
    std::process::exit(i32::from(failed));
}
