//! The output files, checked before any work: a run that cannot write its
//! results, or would write them where the user does not expect, fails at
//! once (exit status 2), not after the solve:
//!
//! - the directory must exist, the path must not be a directory;
//! - each output has a fixed format, and its name must say so (`-report
//!   FILE.json`, `-contact_output FILE.csv`, `-vtk FILE.vtu|PATH.pvtu`,
//!   `-plot_* FILE.png`): `-vtk out/x.vtk` would otherwise write `x.pvtu`
//!   and its pieces;
//! - no two outputs (the `.pvtu` pieces included) may be one file, and no
//!   output may be an input (the mesh, an options file): one would silently
//!   overwrite the other. Paths are compared canonicalised where the file
//!   exists, by their canonical directory and name otherwise.

use super::declared::{
    Given, Opt, CONTACT_OUTPUT, HISTORY_OUTPUT, PLOT_CONTACT, PLOT_HISTORY, PLOT_HISTORY_CURVE,
    REPORT, VTK,
};
use super::MeshSource;
use crate::error::{bad, Error};
use std::path::{Component, Path, PathBuf};

/// The output paths of a run.
#[derive(Clone, Debug, Default)]
pub struct Outputs {
    pub report: Option<String>,
    pub contact_output: Option<String>,
    pub vtk: Option<String>,
    pub plot_contact: Option<String>,
    pub plot_history: Option<String>,
    pub history_output: Option<String>,
    pub plot_history_curve: Option<String>,
}

/// An output option: the extensions its file may have, and what it is.
struct Kind {
    opt: &'static Opt<Given>,
    extensions: &'static [&'static str],
    what: &'static str,
}

const KINDS: [Kind; 7] = [
    Kind {
        opt: &REPORT,
        extensions: &[".json"],
        what: "the report is JSON",
    },
    Kind {
        opt: &CONTACT_OUTPUT,
        extensions: &[".csv"],
        what: "the contact table is CSV",
    },
    Kind {
        opt: &VTK,
        extensions: &[".vtu", ".pvtu"],
        what: ".vtu: one file gathered on rank 0; .pvtu: an index and one .vtu piece per rank",
    },
    Kind {
        opt: &PLOT_CONTACT,
        extensions: &[".png"],
        what: "plots are PNG images",
    },
    Kind {
        opt: &PLOT_HISTORY,
        extensions: &[".png"],
        what: "plots are PNG images",
    },
    Kind {
        opt: &HISTORY_OUTPUT,
        extensions: &[".csv"],
        what: "the history table is CSV",
    },
    Kind {
        opt: &PLOT_HISTORY_CURVE,
        extensions: &[".png"],
        what: "plots are PNG images",
    },
];

/// The path of `opt`, if given, with a directory that exists.
fn path_of(opt: &Opt<Given>) -> Result<Option<String>, Error> {
    let Some(path) = opt.word()? else {
        return Ok(None);
    };
    let p = Path::new(&path);
    let dir = parent(p);
    if !dir.is_dir() {
        return bad(format!(
            "option {}: directory '{}' of '{path}' does not exist",
            opt.name,
            dir.display()
        ));
    }
    if p.is_dir() || path.ends_with('/') {
        return bad(format!("option {}: '{path}' is a directory", opt.name));
    }
    Ok(Some(path))
}

fn parent(p: &Path) -> &Path {
    p.parent()
        .filter(|d| !d.as_os_str().is_empty())
        .unwrap_or(Path::new("."))
}

/// `p` made absolute, `.` and `..` resolved by the letters alone.
fn lexical(p: &Path) -> PathBuf {
    let abs = if p.is_absolute() {
        p.to_path_buf()
    } else {
        std::env::current_dir().unwrap_or_default().join(p)
    };
    let mut out = PathBuf::new();
    for c in abs.components() {
        match c {
            Component::CurDir => {}
            Component::ParentDir => {
                out.pop();
            }
            other => out.push(other),
        }
    }
    out
}

/// What `path` names, for comparisons: canonical where the file exists,
/// else its canonical directory joined with its name, else lexical.
pub fn identity(path: &str) -> PathBuf {
    let p = Path::new(path);
    if let Ok(c) = std::fs::canonicalize(p) {
        return c;
    }
    if let (Ok(dir), Some(name)) = (std::fs::canonicalize(parent(p)), p.file_name()) {
        if name != ".." {
            return dir.join(name);
        }
    }
    lexical(p)
}

/// The `.vtu` pieces `-vtk PATH.pvtu` writes beside its index, as
/// `report::files::write_vtk` names them: `{stem}_{rank}.vtu`.
fn pvtu_pieces(path: &str, ranks: usize) -> Vec<String> {
    let p = Path::new(path);
    let stem = p
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    let dir = p.parent().unwrap_or(Path::new(""));
    (0..ranks)
        .map(|r| dir.join(format!("{stem}_{r}.vtu")).display().to_string())
        .collect()
}

impl Outputs {
    /// Reads and checks the output options. `inputs`: the options files
    /// of the run; `mesh`: the mesh; `ranks`: the number of ranks (the
    /// `.pvtu` pieces).
    pub fn read(
        mesh: &MeshSource,
        options_files: &[String],
        ranks: usize,
    ) -> Result<Outputs, Error> {
        let mut paths: Vec<(&Kind, String)> = Vec::new();
        for kind in &KINDS {
            if let Some(p) = path_of(kind.opt)? {
                paths.push((kind, p));
            }
        }
        // Every file written, with the option that writes it.
        let mut written: Vec<(String, String, PathBuf)> = Vec::new();
        for (kind, p) in &paths {
            written.push((kind.opt.name.to_string(), p.clone(), identity(p)));
            if kind.opt.name == VTK.name && p.ends_with(".pvtu") {
                for (r, piece) in pvtu_pieces(p, ranks).into_iter().enumerate() {
                    let label = format!("{} (its piece of rank {r}, '{piece}')", kind.opt.name);
                    if Path::new(&piece).is_dir() {
                        return bad(format!("option {label}: '{piece}' is a directory"));
                    }
                    let id = identity(&piece);
                    written.push((label, piece, id));
                }
            }
        }
        for (i, (a, path, id)) in written.iter().enumerate() {
            if let Some((b, _, _)) = written[..i].iter().find(|(_, _, other)| other == id) {
                return bad(format!(
                    "options {b} and {a} name the same file '{path}': each output needs a file of its own"
                ));
            }
        }
        let mut inputs: Vec<(String, &str)> = Vec::new();
        if let MeshSource::File(f) = mesh {
            inputs.push(("the input mesh (-mesh)".into(), f));
        }
        for f in options_files {
            inputs.push(("an options file of this run (-options_file)".into(), f));
        }
        for (what, input) in &inputs {
            let id = identity(input);
            if let Some((a, path, _)) = written.iter().find(|(_, _, w)| *w == id) {
                return bad(format!(
                    "option {a}: '{path}' is {what}: an output must not overwrite an input"
                ));
            }
        }
        for (kind, p) in &paths {
            if !kind.extensions.iter().any(|e| p.ends_with(e)) {
                let ext = kind.extensions.join(" or ");
                return bad(format!(
                    "option {}: '{p}' must end in {ext} ({})",
                    kind.opt.name, kind.what
                ));
            }
        }
        let get = |opt: &Opt<Given>| {
            paths
                .iter()
                .find(|(k, _)| k.opt.name == opt.name)
                .map(|(_, p)| p.clone())
        };
        Ok(Outputs {
            report: get(&REPORT),
            contact_output: get(&CONTACT_OUTPUT),
            vtk: get(&VTK),
            plot_contact: get(&PLOT_CONTACT),
            plot_history: get(&PLOT_HISTORY),
            history_output: get(&HISTORY_OUTPUT),
            plot_history_curve: get(&PLOT_HISTORY_CURVE),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pieces_are_named_as_the_writer_names_them() {
        assert_eq!(
            pvtu_pieces("out/x.pvtu", 2),
            vec!["out/x_0.vtu".to_string(), "out/x_1.vtu".to_string()]
        );
        assert_eq!(pvtu_pieces("x.pvtu", 1), vec!["x_0.vtu".to_string()]);
    }

    #[test]
    fn identities_see_through_dots() {
        assert_eq!(identity("./a/../b.json"), identity("b.json"));
        assert_eq!(identity("src/../Cargo.toml"), identity("Cargo.toml"));
        assert_eq!(
            identity("no_such_dir/../x.json"),
            std::env::current_dir().unwrap().join("x.json")
        );
    }
}
