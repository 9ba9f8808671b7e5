//! Load histories (`-load_steps N`, `-load_history FILE`): the factor of
//! each load group at each step. The groups are the load options of the
//! run: `-traction_NAME`, `-pressure_NAME`, `-dirichlet_NAME` (its
//! prescribed values) and the body force (`-body_force`, `-gravity`);
//! K and B do not depend on them, so one factorization serves every step.

use super::declared::{HISTORY_CURVE, LOAD_HISTORY, LOAD_STEPS};
use super::{DirichletBc, PressureBc, TractionBc};
use crate::error::{bad, Error};

/// A load group of a history: what one column scales.
#[derive(Clone, Debug, PartialEq)]
pub enum LoadGroup {
    /// Every load and prescribed displacement (`step,factor`).
    All,
    Traction(String),
    Pressure(String),
    Dirichlet(String),
    Body,
}

impl LoadGroup {
    /// The column name (`traction_top`, `body`, `factor`).
    pub fn name(&self) -> String {
        match self {
            LoadGroup::All => "factor".into(),
            LoadGroup::Traction(g) => format!("traction_{g}"),
            LoadGroup::Pressure(g) => format!("pressure_{g}"),
            LoadGroup::Dirichlet(g) => format!("dirichlet_{g}"),
            LoadGroup::Body => "body".into(),
        }
    }
}

/// The steps of a load history.
#[derive(Clone, Debug)]
pub struct LoadHistory {
    /// The groups the columns scale: `[All]`, or named groups (the loads
    /// not named keep their full value at every step).
    pub groups: Vec<LoadGroup>,
    /// Per step, one factor per group.
    pub factors: Vec<Vec<f64>>,
    /// Where it came from, for messages (`-load_steps 10`, the file).
    pub source: String,
    /// `-history_curve`: the group and the component of the curve (None:
    /// chosen from the loads).
    pub curve: Option<(LoadGroup, Option<usize>)>,
}

/// The loads a history may name.
pub struct Loads<'a> {
    pub dirichlet: &'a [DirichletBc],
    pub traction: &'a [TractionBc],
    pub pressure: &'a [PressureBc],
    pub body: bool,
}

impl Loads<'_> {
    /// The group a column or `-history_curve` names, if the run has it.
    fn group(&self, word: &str) -> Option<LoadGroup> {
        if word == "body" {
            return self.body.then_some(LoadGroup::Body);
        }
        let (kind, name) = word.split_once('_')?;
        match kind {
            "traction" if self.traction.iter().any(|t| t.group == name) => {
                Some(LoadGroup::Traction(name.into()))
            }
            "pressure" if self.pressure.iter().any(|t| t.group == name) => {
                Some(LoadGroup::Pressure(name.into()))
            }
            "dirichlet" if self.dirichlet.iter().any(|t| t.group == name) => {
                Some(LoadGroup::Dirichlet(name.into()))
            }
            _ => None,
        }
    }

    /// Every group of the run, as `-history_curve` and the columns name
    /// them (for messages).
    fn names(&self) -> String {
        let mut v: Vec<String> = Vec::new();
        v.extend(
            self.traction
                .iter()
                .map(|t| format!("traction_{}", t.group)),
        );
        v.extend(
            self.pressure
                .iter()
                .map(|t| format!("pressure_{}", t.group)),
        );
        v.extend(
            self.dirichlet
                .iter()
                .map(|t| format!("dirichlet_{}", t.group)),
        );
        if self.body {
            v.push("body".into());
        }
        if v.is_empty() {
            "none".into()
        } else {
            v.join(", ")
        }
    }
}

/// The most steps a load history may have: each solves the contact
/// problem at least once, and the history keeps a row per step (its table
/// and curve); a count beyond this is a slip of the keyboard (1e8 steps
/// took 12 GB before the first solve, and would run for days).
pub const MAX_STEPS: usize = 1_000_000;

/// Why a history cannot have more than [`MAX_STEPS`] steps.
fn too_many() -> String {
    format!("a load history has at most {MAX_STEPS} steps (each solves the contact problem at least once)")
}

/// Reads `-load_steps`, `-load_history` and `-history_curve` (None: one
/// solve at the full load).
pub fn read(loads: &Loads) -> Result<Option<LoadHistory>, Error> {
    let steps = LOAD_STEPS.count()?;
    let file = LOAD_HISTORY.word()?;
    let mut history = match (steps, file) {
        (Some(_), Some(_)) => {
            return bad("options -load_steps and -load_history: give one of them, not both")
        }
        (Some(0), None) => return bad("option -load_steps: 0 steps (give N >= 1)"),
        (Some(n), None) if n > MAX_STEPS => {
            return bad(format!("option -load_steps {n}: {}", too_many()))
        }
        (Some(n), None) => LoadHistory {
            groups: vec![LoadGroup::All],
            factors: (1..=n).map(|k| vec![k as f64 / n as f64]).collect(),
            source: format!("-load_steps {n}"),
            curve: None,
        },
        (None, Some(f)) => {
            let text = std::fs::read_to_string(&f).or_else(|e| {
                let hint = super::files::path_hint("-load_history", &f);
                bad(format!(
                    "option -load_history: cannot read '{f}': {e}{hint}"
                ))
            })?;
            parse(&f, &text, loads)?
        }
        (None, None) => {
            if HISTORY_CURVE.is_set()? {
                return bad(
                    "option -history_curve needs a load history (-load_steps or -load_history)",
                );
            }
            return Ok(None);
        }
    };
    history.curve = curve(loads)?;
    Ok(Some(history))
}

/// `-history_curve GROUP[,ux|uy|uz]`.
fn curve(loads: &Loads) -> Result<Option<(LoadGroup, Option<usize>)>, Error> {
    let Some(words) = HISTORY_CURVE.words()? else {
        return Ok(None);
    };
    let name = HISTORY_CURVE.name;
    if words.len() > 2 {
        return bad(format!(
            "option {name}: '{}' is not GROUP[,ux|uy|uz]",
            words.join(",")
        ));
    }
    let Some(group) = loads.group(&words[0]) else {
        return bad(format!(
            "option {name}: '{}' is not a load group of this run ({})",
            words[0],
            loads.names()
        ));
    };
    let comp = match words.get(1).map(String::as_str) {
        None => None,
        Some("ux") => Some(0),
        Some("uy") => Some(1),
        Some("uz") => Some(2),
        Some(other) => {
            return bad(format!(
                "option {name}: unknown component '{other}' (ux, uy, uz)"
            ))
        }
    };
    Ok(Some((group, comp)))
}

/// The table of `-load_history` (`path` for messages).
pub fn parse(path: &str, text: &str, loads: &Loads) -> Result<LoadHistory, Error> {
    let err = |line: usize, what: String| -> Result<LoadHistory, Error> {
        bad(format!(
            "option -load_history: '{path}' line {line}: {what}"
        ))
    };
    // A spreadsheet's "CSV UTF-8" starts with a byte-order mark.
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let mut rows = text
        .lines()
        .enumerate()
        .map(|(i, l)| (i + 1, l.split('#').next().unwrap_or("").trim()))
        .filter(|(_, l)| !l.is_empty());
    let Some((hl, header)) = rows.next() else {
        return bad(format!(
            "option -load_history: '{path}' has no table (a header 'step,factor' or 'step,GROUP,...', then one row per step)"
        ));
    };
    let cols: Vec<&str> = header.split(',').map(str::trim).collect();
    if cols[0] != "step" || cols.len() < 2 {
        return err(
            hl,
            format!("the header '{header}' must be 'step,factor' or 'step,GROUP,...'"),
        );
    }
    if let Some(i) = cols.iter().position(|c| c.is_empty()) {
        return err(
            hl,
            format!(
                "column {} of the header '{header}' has no name (a comma too many?)",
                i + 1
            ),
        );
    }
    let mut groups = Vec::new();
    for c in &cols[1..] {
        let g = if *c == "factor" && cols.len() == 2 {
            LoadGroup::All
        } else if let Some(g) = loads.group(c) {
            g
        } else {
            return err(
                hl,
                format!(
                    "column '{c}' is not a load group of this run (groups: {}; or a single column 'factor')",
                    loads.names()
                ),
            );
        };
        if groups.contains(&g) {
            return err(hl, format!("column '{c}' appears twice"));
        }
        groups.push(g);
    }
    let mut factors = Vec::new();
    for (line, row) in rows {
        let v: Vec<&str> = row.split(',').map(str::trim).collect();
        if v.len() != cols.len() {
            return err(
                line,
                format!("{} values, the header has {}", v.len(), cols.len()),
            );
        }
        let expected = factors.len() + 1;
        if expected > MAX_STEPS {
            return err(line, format!("step {expected}: {}", too_many()));
        }
        if v[0].parse::<usize>().ok() != Some(expected) {
            return err(
                line,
                format!(
                    "step '{}' where step {expected} was expected (steps count 1, 2, 3, ...)",
                    v[0]
                ),
            );
        }
        let mut f = Vec::with_capacity(groups.len());
        for (c, x) in cols[1..].iter().zip(&v[1..]) {
            match x.parse::<f64>() {
                Ok(a) if a.is_finite() => f.push(a),
                _ => return err(line, format!("'{x}' (column {c}) is not a finite number")),
            }
        }
        factors.push(f);
    }
    if factors.is_empty() {
        return bad(format!(
            "option -load_history: '{path}' has a header and no step"
        ));
    }
    Ok(LoadHistory {
        groups,
        factors,
        source: format!("-load_history {path}"),
        curve: None,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn loads<'a>(d: &'a [DirichletBc], t: &'a [TractionBc]) -> Loads<'a> {
        Loads {
            dirichlet: d,
            traction: t,
            pressure: &[],
            body: false,
        }
    }

    #[test]
    fn tables_read_and_bad_ones_name_the_line() {
        let t = [TractionBc {
            group: "top".into(),
            traction: vec![0.0, -1.0],
        }];
        let d = [DirichletBc {
            group: "left".into(),
            comps: vec![(0, 0.0)],
        }];
        let l = loads(&d, &t);
        let h = parse(
            "h.csv",
            "# loading\nstep,factor\n1,0.5\n2,1\n3, 0.25 # back\n",
            &l,
        )
        .unwrap();
        assert_eq!(h.groups, vec![LoadGroup::All]);
        assert_eq!(h.factors, vec![vec![0.5], vec![1.0], vec![0.25]]);
        // Saved by a spreadsheet: a byte-order mark and CRLF line ends.
        let h = parse("h.csv", "\u{feff}step,factor\r\n1,0.5\r\n2,1\r\n", &l).unwrap();
        assert_eq!(h.factors, vec![vec![0.5], vec![1.0]]);
        let h = parse(
            "h.csv",
            "step,traction_top,dirichlet_left\n1,1,0\n2,1,0.5\n",
            &l,
        )
        .unwrap();
        assert_eq!(
            h.groups,
            vec![
                LoadGroup::Traction("top".into()),
                LoadGroup::Dirichlet("left".into())
            ]
        );
        let e = |text: &str| parse("h.csv", text, &l).unwrap_err().to_string();
        assert!(e("").contains("has no table"));
        assert!(e("step,factor\n").contains("a header and no step"));
        assert!(e("step,factor,\n1,1,\n").contains(
            "line 1: column 3 of the header 'step,factor,' has no name (a comma too many?)"
        ));
        assert!(e("step,traction_bottom\n1,1\n").contains("line 1: column 'traction_bottom' is not a load group of this run (groups: traction_top, dirichlet_left"));
        assert!(e("step,factor\n1,1\n3,1\n").contains("line 3: step '3' where step 2"));
        assert!(
            e("step,factor\n1,x\n").contains("line 2: 'x' (column factor) is not a finite number")
        );
        assert!(e("step,factor\n1,1,2\n").contains("line 2: 3 values, the header has 2"));
        assert!(e("factor\n1\n").contains("must be 'step,factor'"));
        assert!(e("step,traction_top,traction_top\n").contains("appears twice"));
        let mut long = String::from("step,factor\n");
        for k in 1..=MAX_STEPS + 1 {
            long.push_str(&format!("{k},1\n"));
        }
        assert!(e(&long).contains(&format!(
            "line {}: step {}: a load history has at most {MAX_STEPS} steps",
            MAX_STEPS + 2,
            MAX_STEPS + 1
        )));
    }
}
