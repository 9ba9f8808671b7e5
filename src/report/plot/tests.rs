use super::canvas::read_font;
use super::*;
use std::path::PathBuf;

/// A convergence plot: each `(label, values)` against `iterations`, as
/// lines on a logarithmic y axis.
fn plot_history(
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
