//! What the user sees: the summary on rank 0, the JSON report, the contact
//! CSV, and the comparison with the analytic Hertz pressure.
//!
//! Contact data are gathered on rank 0 (candidates are a surface: few), sorted
//! by the node's tag in the input mesh. Files are written atomically
//! (temporary file in the same directory, then rename).

pub mod plot;
pub mod vtk;

use crate::error::Error;
use crate::options::HertzReference;
use mpi::traits::*;
use std::fmt::Write as _;
use std::io::Write as _;

/// Number of f64 values per contact row on the wire.
pub const ROW_LEN: usize = 16;

/// One contact candidate, as written to the CSV.
#[derive(Clone, Debug, Default)]
pub struct ContactRow {
    pub node: u64,
    pub x: [f64; 3],
    pub weight: f64,
    pub gap: f64,
    pub un: f64,
    pub ut: [f64; 3],
    pub lambda_n: f64,
    pub lambda_t: [f64; 3],
    /// 0 open, 1 contact, 2 stick, 3 slip.
    pub status: u8,
    /// The friction bound s (0 without friction; not in the CSV).
    pub bound: f64,
}

impl ContactRow {
    pub fn status_name(&self) -> &'static str {
        ["open", "contact", "stick", "slip"][self.status as usize]
    }
    fn pack(&self, out: &mut Vec<f64>) {
        out.push(self.node as f64);
        out.extend_from_slice(&self.x);
        out.push(self.weight);
        out.push(self.gap);
        out.push(self.un);
        out.extend_from_slice(&self.ut);
        out.push(self.lambda_n);
        out.extend_from_slice(&self.lambda_t);
        out.push(self.status as f64);
        out.push(self.bound);
    }
    fn unpack(v: &[f64]) -> ContactRow {
        ContactRow {
            node: v[0] as u64,
            x: [v[1], v[2], v[3]],
            weight: v[4],
            gap: v[5],
            un: v[6],
            ut: [v[7], v[8], v[9]],
            lambda_n: v[10],
            lambda_t: [v[11], v[12], v[13]],
            status: v[14] as u8,
            bound: v[15],
        }
    }
}

/// Gathers every rank's rows on rank 0, sorted by node tag (empty elsewhere).
pub fn gather_rows<C: Communicator>(world: &C, rows: &[ContactRow]) -> Vec<ContactRow> {
    let mut buf = Vec::with_capacity(rows.len() * ROW_LEN);
    for r in rows {
        r.pack(&mut buf);
    }
    let root = world.process_at_rank(0);
    if world.rank() == 0 {
        let mut all: Vec<ContactRow> = buf.chunks(ROW_LEN).map(ContactRow::unpack).collect();
        for p in 1..world.size() {
            let (v, _) = world.process_at_rank(p).receive_vec::<f64>();
            all.extend(v.chunks(ROW_LEN).map(ContactRow::unpack));
        }
        all.sort_by_key(|r| r.node);
        all
    } else {
        root.send(&buf[..]);
        Vec::new()
    }
}

/// Sends rank 0's rows to every rank (for outputs every rank writes).
pub fn broadcast_rows<C: Communicator>(world: &C, rows: &[ContactRow]) -> Vec<ContactRow> {
    let root = world.process_at_rank(0);
    let mut buf = Vec::new();
    if world.rank() == 0 {
        for r in rows {
            r.pack(&mut buf);
        }
    }
    let mut len = [buf.len() as u64];
    root.broadcast_into(&mut len[..]);
    buf.resize(len[0] as usize, 0.0);
    root.broadcast_into(&mut buf[..]);
    buf.chunks(ROW_LEN).map(ContactRow::unpack).collect()
}

/// The Hertz comparison, computed on rank 0 from the gathered rows.
#[derive(Clone, Debug, Default)]
pub struct HertzComparison {
    pub error_l2: f64,
    pub error_rel: f64,
    pub peak: f64,
    pub peak_hertz: f64,
    pub half_width: f64,
    pub half_width_hertz: f64,
}

/// Hertz pressure at distance `x` from the centre, and (p0, b or a).
pub fn hertz_pressure(dim: usize, force: f64, radius: f64, e_star: f64, x: f64) -> (f64, f64, f64) {
    use std::f64::consts::PI;
    if dim == 2 {
        // Cylinder on a plane: b = 2 sqrt(F R / (pi E*)), p = 2F/(pi b^2) sqrt(b^2 - x^2).
        let b = 2.0 * (force * radius / (PI * e_star)).sqrt();
        let p0 = 2.0 * force / (PI * b);
        let p = if x < b {
            2.0 * force / (PI * b * b) * (b * b - x * x).sqrt()
        } else {
            0.0
        };
        (p, p0, b)
    } else {
        // Sphere: a = (3FR/(4E*))^(1/3), p0 = 3F/(2 pi a^2).
        let a = (3.0 * force * radius / (4.0 * e_star)).cbrt();
        let p0 = 3.0 * force / (2.0 * PI * a * a);
        let p = if x < a {
            p0 * (1.0 - x * x / (a * a)).sqrt()
        } else {
            0.0
        };
        (p, p0, a)
    }
}

pub fn compare_hertz(
    rows: &[ContactRow],
    dim: usize,
    n: &[f64],
    e_star: f64,
    reference: &HertzReference,
) -> HertzComparison {
    let center: Vec<f64> = match &reference.center {
        Some(c) => c.clone(),
        None => rows
            .iter()
            .min_by(|a, b| a.gap.total_cmp(&b.gap))
            .map(|r| r.x[..dim].to_vec())
            .unwrap_or(vec![0.0; dim]),
    };
    let dist = |r: &ContactRow| {
        let dx: Vec<f64> = (0..dim).map(|k| r.x[k] - center[k]).collect();
        let dn: f64 = dx.iter().zip(n).map(|(a, b)| a * b).sum();
        dx.iter()
            .zip(n)
            .map(|(a, b)| (a - dn * b).powi(2))
            .sum::<f64>()
            .sqrt()
    };
    let mut err2 = 0.0;
    let mut p2 = 0.0;
    let mut out = HertzComparison::default();
    for r in rows {
        let x = dist(r);
        let (p, p0, b) = hertz_pressure(dim, reference.force, reference.radius, e_star, x);
        err2 += r.weight * (r.lambda_n - p).powi(2);
        p2 += r.weight * p * p;
        out.peak = out.peak.max(r.lambda_n);
        out.peak_hertz = p0;
        out.half_width_hertz = b;
        if r.status != 0 && r.lambda_n > 0.0 {
            out.half_width = out.half_width.max(x);
        }
    }
    out.error_l2 = err2.sqrt();
    out.error_rel = if p2 > 0.0 { (err2 / p2).sqrt() } else { 0.0 };
    out
}

/// Writes `contents` to `path` atomically: a temporary file in the same
/// directory, then a rename. A failure names the option and the file.
pub fn write_atomic(option: &str, path: &str, contents: &[u8]) -> Result<(), Error> {
    let target = std::path::Path::new(path);
    let dir = target
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(std::path::Path::new("."));
    let name = target
        .file_name()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    let tmp = dir.join(format!(".{name}.tmp{}", std::process::id()));
    let result = (|| -> std::io::Result<()> {
        let mut f = std::fs::File::create(&tmp)?;
        f.write_all(contents)?;
        f.sync_all()?;
        std::fs::rename(&tmp, target)
    })();
    result.map_err(|e| {
        let _ = std::fs::remove_file(&tmp);
        Error::BadInput(format!("option {option}: cannot write '{path}': {e}"))
    })
}

pub fn csv(rows: &[ContactRow]) -> String {
    let mut s = String::from(
        "node,x,y,z,weight,gap,un,ut_x,ut_y,ut_z,lambda_n,lambda_t_x,lambda_t_y,lambda_t_z,status\n",
    );
    for r in rows {
        let _ = writeln!(
            s,
            "{},{:e},{:e},{:e},{:e},{:e},{:e},{:e},{:e},{:e},{:e},{:e},{:e},{:e},{}",
            r.node,
            r.x[0],
            r.x[1],
            r.x[2],
            r.weight,
            r.gap,
            r.un,
            r.ut[0],
            r.ut[1],
            r.ut[2],
            r.lambda_n,
            r.lambda_t[0],
            r.lambda_t[1],
            r.lambda_t[2],
            r.status_name()
        );
    }
    s
}

/// A minimal JSON object writer (keys in insertion order).
#[derive(Default)]
pub struct Json {
    items: Vec<(String, String)>,
}

fn json_f64(v: f64) -> String {
    if v.is_finite() {
        format!("{v:e}")
    } else {
        "null".into()
    }
}

impl Json {
    pub fn num(&mut self, k: &str, v: f64) -> &mut Self {
        self.items.push((k.into(), json_f64(v)));
        self
    }
    pub fn int(&mut self, k: &str, v: usize) -> &mut Self {
        self.items.push((k.into(), v.to_string()));
        self
    }
    pub fn opt(&mut self, k: &str, v: Option<f64>) -> &mut Self {
        self.items
            .push((k.into(), v.map(json_f64).unwrap_or_else(|| "null".into())));
        self
    }
    pub fn boolean(&mut self, k: &str, v: bool) -> &mut Self {
        self.items.push((k.into(), v.to_string()));
        self
    }
    pub fn string(&mut self, k: &str, v: &str) -> &mut Self {
        let escaped: String = v
            .chars()
            .flat_map(|c| match c {
                '"' => "\\\"".chars().collect::<Vec<_>>(),
                '\\' => "\\\\".chars().collect(),
                c if (c as u32) < 0x20 => format!("\\u{:04x}", c as u32).chars().collect(),
                c => vec![c],
            })
            .collect();
        self.items.push((k.into(), format!("\"{escaped}\"")));
        self
    }
    pub fn array(&mut self, k: &str, v: &[f64]) -> &mut Self {
        let inner: Vec<String> = v.iter().map(|&x| json_f64(x)).collect();
        self.items
            .push((k.into(), format!("[{}]", inner.join(", "))));
        self
    }
    pub fn int_array(&mut self, k: &str, v: &[usize]) -> &mut Self {
        let inner: Vec<String> = v.iter().map(|x| x.to_string()).collect();
        self.items
            .push((k.into(), format!("[{}]", inner.join(", "))));
        self
    }
    pub fn render(&self) -> String {
        let body: Vec<String> = self
            .items
            .iter()
            .map(|(k, v)| format!("  \"{k}\": {v}"))
            .collect();
        format!("{{\n{}\n}}\n", body.join(",\n"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hertz_2d_integrates_to_the_force() {
        // The integral of p over (-b, b) is F.
        let (f, r, e) = (1600.0, 8.0, 2000.0 / (1.0 - 0.09));
        let (_, _, b) = hertz_pressure(2, f, r, e, 0.0);
        let m = 200000;
        let h = 2.0 * b / m as f64;
        let total: f64 = (0..m)
            .map(|i| hertz_pressure(2, f, r, e, (-b + (i as f64 + 0.5) * h).abs()).0 * h)
            .sum();
        assert!((total - f).abs() < 1e-3 * f);
    }

    #[test]
    fn hertz_3d_integrates_to_the_force() {
        let (f, r, e) = (1000.0, 0.5, 1e6);
        let (_, _, a) = hertz_pressure(3, f, r, e, 0.0);
        let m = 100000;
        let h = a / m as f64;
        let total: f64 = (0..m)
            .map(|i| {
                let x = (i as f64 + 0.5) * h;
                hertz_pressure(3, f, r, e, x).0 * 2.0 * std::f64::consts::PI * x * h
            })
            .sum();
        assert!((total - f).abs() < 1e-3 * f);
    }

    #[test]
    fn json_escapes_and_nulls() {
        let mut j = Json::default();
        j.string("a", "x\"y")
            .num("b", f64::NAN)
            .opt("c", None)
            .int("d", 3);
        let s = j.render();
        assert!(s.contains("\"a\": \"x\\\"y\""));
        assert!(s.contains("\"b\": null"));
        assert!(s.contains("\"c\": null"));
    }

    #[test]
    fn atomic_write_leaves_no_temporary() {
        let dir = std::env::temp_dir().join(format!("ubr-atomic-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join("out.json");
        write_atomic("-report", p.to_str().unwrap(), b"{}").unwrap();
        assert_eq!(std::fs::read(&p).unwrap(), b"{}");
        let names: Vec<_> = std::fs::read_dir(&dir).unwrap().collect();
        assert_eq!(names.len(), 1);
        let bad = dir.join("missing/out.json");
        let e = write_atomic("-report", bad.to_str().unwrap(), b"{}").unwrap_err();
        assert!(e.to_string().contains("-report"));
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
