//! Options files, read by the program before PETSc starts: every
//! `-options_file FILE` of the command line (and of `PETSC_OPTIONS`, and of
//! such a file) is replaced in place by the options the file holds, so that
//! PETSc sees the same options in the same order (a later option still wins)
//! and every mistake in a file is ours to name in one line, with its file and
//! line, before any work:
//!
//! - a file that includes itself, directly or through others (PETSc would
//!   recurse until the stack overflows);
//! - a file that cannot be read;
//! - a line PETSc would refuse: a value with a space that is not in double
//!   quotes (PETSc's files know double quotes: `-mesh "my dir/m.msh"`), two
//!   options on a line, a first word that is not an option.
//!
//! A UTF-8 byte-order mark (which editors on Windows write) is skipped.
//! Read as PETSc reads them (`PetscOptionsInsertFilePetsc` of 3.18): `#`
//! starts a comment, a token is a word or a double-quoted string, a line is
//! `-name [value]` or `alias -new -old`. A file PETSc must read itself (YAML,
//! a name with `${...}` for PETSc to substitute, a file with `alias` lines)
//! is left in place for PETSc, its nested files still checked for cycles.
//!
//! Rank 0 reads the files (as PETSc does) and `main` broadcasts the outcome.

use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

/// What PETSc starts with.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Expanded {
    /// The command line, every options file expanded in place.
    pub args: Vec<String>,
    /// The new value of `PETSC_OPTIONS` (None: as it is).
    pub env: Option<String>,
    /// Every options file read, as named.
    pub files: Vec<String>,
    /// The warnings of the overrides a user probably did not mean (an
    /// options file over a value the command line gave before it, one file
    /// giving an option twice); PETSc takes the later value.
    pub overridden: Vec<String>,
    /// The options whose last value an options file gave: (name in lower
    /// case without its dash, file as named, line), for the hint of a
    /// relative path that is not found ([`path_hint`]).
    pub origins: Vec<(String, String, usize)>,
}

static READ: OnceLock<Vec<String>> = OnceLock::new();
static OVERRIDDEN: OnceLock<Vec<String>> = OnceLock::new();
static ORIGINS: OnceLock<Vec<(String, String, usize)>> = OnceLock::new();

/// Remembers the options files of the run (for the output checks: no
/// output may overwrite one), the options given twice and where the files'
/// options come from.
pub fn record(e: &Expanded) {
    let _ = READ.set(e.files.clone());
    let _ = OVERRIDDEN.set(e.overridden.clone());
    let _ = ORIGINS.set(e.origins.clone());
}

/// The end of the message of a file that option `option` (e.g. `-mesh`)
/// names as `path` and that cannot be read, where an options file gave it:
/// relative paths are relative to the working directory (PETSc's rule),
/// not to the file, so a user who runs a shipped file from another
/// directory is told where the path is found (empty when the command line
/// gave it, or the path is absolute).
pub fn path_hint(option: &str, path: &str) -> String {
    let lower = option.trim_start_matches('-').to_ascii_lowercase();
    let origin = ORIGINS
        .get()
        .and_then(|o| o.iter().find(|(k, _, _)| *k == lower));
    match origin {
        Some((_, file, line)) => hint_from(&format!("'{file}' line {line}"), file, path),
        None => String::new(),
    }
}

/// [`path_hint`] for `path` named at `from` (a file's line) in `file`:
/// where `path` is found from the file's directory or one above it.
fn hint_from(from: &str, file: &str, path: &str) -> String {
    let p = Path::new(path);
    if p.is_absolute() || p.exists() {
        return String::new();
    }
    let cwd = std::env::current_dir().map_or_else(|_| ".".into(), |d| d.display().to_string());
    let start = std::fs::canonicalize(file).ok();
    let found = start
        .as_deref()
        .and_then(Path::parent)
        .into_iter()
        .flat_map(Path::ancestors)
        .find(|d| d.join(p).exists());
    match found {
        Some(d) => format!(
            " (named in {from}; paths are relative to the working directory, {cwd}; '{path}' is in {}: run there)",
            d.display()
        ),
        None => format!(" (named in {from}; paths are relative to the working directory, {cwd})"),
    }
}

/// The warnings of options given twice with different values (empty
/// before [`record`]).
pub fn overridden() -> &'static [String] {
    OVERRIDDEN.get().map(|v| v.as_slice()).unwrap_or(&[])
}

/// The options files of the run, as named (empty before [`record`]).
pub fn read() -> &'static [String] {
    READ.get().map(|v| v.as_slice()).unwrap_or(&[])
}

/// Expands the options files of `args` (the process's arguments, program
/// name first) and of `env` (`PETSC_OPTIONS`), and checks the files PETSc
/// reads by itself (`petscrc`: `~/.petscrc`, `.petscrc`, `petscrc`, unless
/// `-skip_petscrc`). The error is the one-line message of exit status 2.
pub fn expand(args: &[String], env: Option<&str>, petscrc: &[PathBuf]) -> Result<Expanded, String> {
    let mut w = Walker::default();
    let mut out = Vec::with_capacity(args.len());
    out.extend(args.first().cloned());
    // PETSc reads PETSC_OPTIONS and its start-up files before the command
    // line: only the command line's order is followed for overrides.
    w.track = true;
    w.words(&args[args.len().min(1)..], "the command line", &mut out)?;
    w.track = false;
    let env = match env {
        Some(e) if tokens(e).iter().any(|t| is_options_file(t)) => {
            let mut words = Vec::new();
            w.words(&tokens(e), "PETSC_OPTIONS", &mut words)?;
            Some(
                words
                    .iter()
                    .map(|t| {
                        if t.is_empty() || t.contains(' ') {
                            format!("\"{t}\"")
                        } else {
                            t.clone()
                        }
                    })
                    .collect::<Vec<_>>()
                    .join(" "),
            )
        }
        _ => None,
    };
    if !args.iter().any(|a| a.eq_ignore_ascii_case("-skip_petscrc")) {
        for f in petscrc.iter().filter(|f| f.is_file()) {
            let name = f.display().to_string();
            w.file(&name, "PETSc's start-up files", &mut Vec::new(), true)?;
        }
    }
    let overridden = w.overrides();
    let mut origins: Vec<_> = (w.seen.iter())
        .filter_map(|(k, g)| Some((k.clone(), g.file.clone()?, g.line)))
        .collect();
    origins.sort();
    Ok(Expanded {
        args: out,
        env,
        files: w.files,
        overridden,
        origins,
    })
}

/// The files PETSc reads at start-up by itself.
pub fn petscrc_files() -> Vec<PathBuf> {
    let mut v = Vec::new();
    if let Some(home) = std::env::var_os("HOME") {
        v.push(Path::new(&home).join(".petscrc"));
    }
    v.push(PathBuf::from(".petscrc"));
    v.push(PathBuf::from("petscrc"));
    v
}

fn is_options_file(t: &str) -> bool {
    t.eq_ignore_ascii_case("-options_file")
}

pub use crate::petsc::options::is_key;

/// A line split as PETSc's `PetscTokenFind` splits it: on spaces; a token
/// that starts with a double quote runs to the next one (quotes removed).
/// `Err` on a quote left open.
fn split(line: &str) -> Result<Vec<String>, ()> {
    let mut out = Vec::new();
    let mut rest = line.trim_start_matches(' ');
    while !rest.is_empty() {
        if let Some(q) = rest.strip_prefix('"') {
            let end = q.find('"').ok_or(())?;
            out.push(q[..end].to_string());
            rest = &q[end + 1..];
        } else {
            let end = rest.find(' ').unwrap_or(rest.len());
            out.push(rest[..end].to_string());
            rest = &rest[end..];
        }
        rest = rest.trim_start_matches(' ');
    }
    Ok(out)
}

/// [`split`] for `PETSC_OPTIONS` (an open quote runs to the end, as in PETSc).
fn tokens(s: &str) -> Vec<String> {
    split(s).unwrap_or_else(|()| {
        let (head, tail) = s.rsplit_once('"').unwrap_or((s, ""));
        let mut v = split(head).unwrap_or_default();
        v.push(tail.to_string());
        v
    })
}

/// One line of an options file.
#[derive(Debug, PartialEq)]
enum Line {
    Option { key: String, value: Option<String> },
    Alias,
}

/// The options of a file's text, with their line numbers; `Err` names the
/// line. A UTF-8 byte-order mark is skipped.
fn parse(bytes: &[u8], file: &str) -> Result<(Vec<(usize, Line)>, bool), String> {
    if bytes.starts_with(&[0xFF, 0xFE]) || bytes.starts_with(&[0xFE, 0xFF]) {
        return Err(format!(
            "options file '{file}' is UTF-16 text: save it as UTF-8 (or ASCII)"
        ));
    }
    let bom = bytes.starts_with(&[0xEF, 0xBB, 0xBF]);
    let bytes = if bom { &bytes[3..] } else { bytes };
    let mut out = Vec::new();
    for (i, raw) in bytes.split(|&b| b == b'\n').enumerate() {
        let n = i + 1;
        let raw = match raw.iter().position(|&b| b == b'#') {
            Some(p) => &raw[..p],
            None => raw,
        };
        let Ok(text) = std::str::from_utf8(raw) else {
            return Err(format!("options file '{file}' line {n}: not UTF-8 text"));
        };
        let text = text.replace(['\t', '\r'], " ");
        let Ok(t) = split(&text) else {
            return Err(format!(
                "options file '{file}' line {n}: a double quote is not closed: {}",
                text.trim()
            ));
        };
        let Some(first) = t.first() else {
            continue;
        };
        if first.starts_with('-') {
            if !is_key(first) {
                return Err(format!(
                    "options file '{file}' line {n}: '{first}' is not an option name (a letter follows the '-')"
                ));
            }
            if let Some(second) = t[1..].iter().find(|s| is_key(s)) {
                return Err(format!(
                    "options file '{file}' line {n}: two options on one line ({first} {second}): PETSc takes one option per line"
                ));
            }
            if t.len() > 2 {
                let value = text
                    .trim()
                    .strip_prefix(first.as_str())
                    .unwrap_or("")
                    .trim();
                return Err(format!(
                    "options file '{file}' line {n}: the value of {first} has a space ('{value}' reads as {} words); PETSc's options files take one word per value: write {first} \"{value}\"",
                    t.len() - 1
                ));
            }
            out.push((
                n,
                Line::Option {
                    key: first.clone(),
                    value: t.get(1).cloned(),
                },
            ));
        } else if first.eq_ignore_ascii_case("alias") {
            if t.len() != 3 || !is_key(&t[1]) || !is_key(&t[2]) {
                return Err(format!(
                    "options file '{file}' line {n}: an alias line is 'alias -newname -oldname'"
                ));
            }
            out.push((n, Line::Alias));
        } else {
            return Err(format!(
                "options file '{file}' line {n}: '{first}' is not an option (an option starts with '-', a comment with '#')"
            ));
        }
    }
    Ok((out, bom))
}

/// Whether PETSc reads `name` as YAML (its extension, a `:yaml` suffix, or
/// its first bytes).
fn yaml(name: &str, bytes: &[u8]) -> bool {
    let lower = name.to_ascii_lowercase();
    lower.ends_with(".yml")
        || lower.ends_with(".yaml")
        || lower.ends_with(":yaml")
        || bytes.starts_with(b"%YAML ")
        || bytes.starts_with(b"---")
}

/// The expansion under way: the files open (for cycles) and those read.
#[derive(Default)]
struct Walker {
    /// (canonical path, name as written) of the files being expanded.
    stack: Vec<(PathBuf, String)>,
    files: Vec<String>,
    /// Whether options are followed for overrides (the command line's).
    track: bool,
    /// Each option seen (its name in lower case, as PETSc compares them):
    /// its value and where it was given.
    seen: std::collections::HashMap<String, Given>,
    /// The warnings of one file's repeated options, by option (lower case).
    overridden: Vec<(String, String)>,
    /// The last value the command line itself gave each option.
    command_line: std::collections::HashMap<String, Option<String>>,
}

/// An option's value and where it was given (`file` None: the command line).
struct Given {
    key: String,
    value: Option<String>,
    file: Option<String>,
    line: usize,
}

/// "option -E is given twice: 1 (the command line), then 2 ('f' line 3); ...".
fn override_message(
    key: &str,
    old: &Given,
    value: &Option<String>,
    file: Option<&str>,
    line: usize,
) -> String {
    let at = |f: Option<&str>, l: usize| match f {
        None => "the command line".to_string(),
        Some(f) => format!("'{f}' line {l}"),
    };
    let shown = |v: &Option<String>| v.clone().unwrap_or_else(|| "(no value)".into());
    format!(
        "option {key} is given twice: {} ({}), then {} ({}); the later one, {}, is used (PETSc's rule: the last one given wins)",
        shown(&old.value),
        at(old.file.as_deref(), old.line),
        shown(value),
        at(file, line),
        shown(value)
    )
}

impl Walker {
    /// Follows option `key` given `value` in `file` (None: the command line)
    /// at `line`, for the overrides a user probably did not mean
    /// ([`Walker::overrides`]): one file that gives an option twice with
    /// two values (named unless given again later).
    fn given(&mut self, key: &str, value: Option<&str>, file: Option<&str>, line: usize) {
        if !self.track {
            return;
        }
        let lower = key.trim_start_matches('-').to_ascii_lowercase();
        let value = value.map(str::to_string);
        // Only the option's last override counts.
        self.overridden.retain(|(k, _)| *k != lower);
        if let Some(old) = self.seen.get(&lower) {
            if file.is_some() && old.file.as_deref() == file && old.value != value {
                let message = override_message(key, old, &value, file, line);
                self.overridden.push((lower.clone(), message));
            }
        }
        let given = Given {
            key: key.to_string(),
            value,
            file: file.map(str::to_string),
            line,
        };
        if file.is_none() {
            self.command_line.insert(lower.clone(), given.value.clone());
        }
        self.seen.insert(lower, given);
    }

    /// The warnings of the overrides a user probably did not mean: a file
    /// that takes the last word over a value the command line gave before
    /// it (`-E 1 -options_file f`, f giving `-E 2`: 2 is used), and one file
    /// giving an option twice. A command line that overrides a file's
    /// option, or a file over the options of a file it includes, is the
    /// usual way to vary a scene and says nothing.
    fn overrides(&self) -> Vec<String> {
        let mut out: Vec<(&str, usize, String)> = Vec::new();
        for (lower, last) in &self.seen {
            let (Some(file), Some(earlier)) = (&last.file, self.command_line.get(lower)) else {
                continue;
            };
            if *earlier != last.value {
                let old = Given {
                    key: last.key.clone(),
                    value: earlier.clone(),
                    file: None,
                    line: 0,
                };
                let m = override_message(&last.key, &old, &last.value, Some(file), last.line);
                out.push((file, last.line, m));
            }
        }
        for (lower, m) in &self.overridden {
            let last = &self.seen[lower];
            out.push((last.file.as_deref().unwrap_or(""), last.line, m.clone()));
        }
        out.sort();
        out.into_iter().map(|(_, _, m)| m).collect()
    }

    /// Copies `words` (a command line or `PETSC_OPTIONS`) into `out`,
    /// expanding `-options_file FILE` in place.
    fn words(&mut self, words: &[String], from: &str, out: &mut Vec<String>) -> Result<(), String> {
        let mut i = 0;
        while i < words.len() {
            if is_options_file(&words[i]) {
                match words
                    .get(i + 1)
                    .filter(|f| !f.starts_with('-') && !f.is_empty())
                {
                    Some(f) => self.file(f, from, out, false)?,
                    None => {
                        return Err(format!(
                            "option -options_file (in {from}) needs a file name"
                        ))
                    }
                }
                i += 2;
            } else {
                if is_key(&words[i]) {
                    let value = words.get(i + 1).filter(|v| !is_key(v));
                    self.given(&words[i], value.map(String::as_str), None, 0);
                }
                out.push(words[i].clone());
                i += 1;
            }
        }
        Ok(())
    }

    /// Appends the options of file `name` to `out` (or `-options_file name`
    /// where PETSc must read it itself). `check_only`: a file PETSc reads
    /// itself whatever it holds (petscrc).
    fn file(
        &mut self,
        name: &str,
        from: &str,
        out: &mut Vec<String>,
        check_only: bool,
    ) -> Result<(), String> {
        let keep = |out: &mut Vec<String>| {
            if !check_only {
                out.push("-options_file".into());
                out.push(name.into());
            }
        };
        if name.contains("${") {
            // PETSc substitutes ${PETSC_DIR}, ${HOSTNAME}, ... in the name.
            keep(out);
            return Ok(());
        }
        let path = name.strip_suffix(":yaml").unwrap_or(name);
        let cannot = |e: std::io::Error| {
            let hint = match self.stack.last() {
                Some((_, file)) => hint_from(from, file, path),
                None => String::new(),
            };
            if hint.is_empty() {
                format!("option -options_file: cannot read '{name}' (named in {from}): {e}")
            } else {
                format!("option -options_file: cannot read '{name}': {e}{hint}")
            }
        };
        let canonical = std::fs::canonicalize(path).map_err(cannot)?;
        if let Some(at) = self.stack.iter().position(|(c, _)| *c == canonical) {
            let mut chain: Vec<&str> = self.stack[at..].iter().map(|(_, n)| n.as_str()).collect();
            chain.push(name);
            return Err(format!(
                "option -options_file: options file '{name}' includes itself ({})",
                chain.join(" -> ")
            ));
        }
        if canonical.is_dir() {
            return Err(format!(
                "option -options_file: '{name}' (named in {from}) is a directory"
            ));
        }
        let bytes = std::fs::read(path).map_err(cannot)?;
        self.files.push(path.to_string());
        if yaml(name, &bytes) {
            keep(out);
            return Ok(());
        }
        let (lines, bom) = parse(&bytes, name)?;
        let alias = lines.iter().any(|(_, l)| *l == Line::Alias);
        let petsc_reads = check_only || alias;
        if petsc_reads && bom {
            return Err(format!(
                "options file '{name}' starts with a UTF-8 byte-order mark, which PETSc cannot read{}: save it without (as plain UTF-8)",
                if alias { " in a file with alias lines" } else { "" }
            ));
        }
        if alias && !check_only {
            keep(out);
        }
        self.stack.push((canonical, name.to_string()));
        let mut scratch = Vec::new();
        let sink = if petsc_reads { &mut scratch } else { out };
        for (n, line) in lines {
            let Line::Option { key, value } = line else {
                continue;
            };
            if is_options_file(&key) {
                match value {
                    Some(f) if !f.is_empty() => {
                        self.file(&f, &format!("'{name}' line {n}"), sink, petsc_reads)?
                    }
                    _ => {
                        return Err(format!(
                            "options file '{name}' line {n}: -options_file needs a file name"
                        ))
                    }
                }
            } else {
                if !petsc_reads {
                    self.given(&key, value.as_deref(), Some(name), n);
                }
                sink.push(key);
                sink.extend(value);
            }
        }
        self.stack.pop();
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn s(v: &[&str]) -> Vec<String> {
        v.iter().map(|x| x.to_string()).collect()
    }

    fn dir(name: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("ubr-files-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).unwrap();
        d
    }

    #[test]
    fn keys_as_petsc_reads_them() {
        assert!(is_key("-mesh"));
        assert!(is_key("--mesh"));
        assert!(is_key("-info"));
        assert!(is_key("-inf_x"));
        assert!(!is_key("-1,0"));
        assert!(!is_key("-0.5"));
        assert!(!is_key("-inf"));
        assert!(!is_key("-NaN"));
        assert!(!is_key("mesh"));
        assert!(!is_key("-"));
    }

    #[test]
    fn lines_split_on_spaces_and_double_quotes() {
        assert_eq!(split("  -mesh  a.msh ").unwrap(), s(&["-mesh", "a.msh"]));
        assert_eq!(
            split("-mesh \"my dir/m.msh\"").unwrap(),
            s(&["-mesh", "my dir/m.msh"])
        );
        assert!(split("-mesh \"my dir").is_err());
    }

    /// The options a file gave are remembered with the file and line, and
    /// a relative path that is not found here is looked for from the file's
    /// directory upwards.
    #[test]
    fn origins_and_where_a_relative_path_is() {
        let d = dir("origins");
        std::fs::create_dir_all(d.join("opts").join("deep")).unwrap();
        std::fs::write(d.join("m.msh"), "").unwrap();
        let scene = d.join("opts").join("deep").join("scene");
        std::fs::write(&scene, "-E 1\n-Mesh m.msh\n").unwrap();
        let sc = scene.display().to_string();
        let origins = |args: &[&str]| {
            let mut a = s(&["prog", "-options_file", &sc]);
            a.extend(s(args));
            expand(&a, None, &[]).unwrap().origins
        };
        let o = origins(&["-nu", "0.3"]);
        assert_eq!(
            o,
            [("e".into(), sc.clone(), 1), ("mesh".into(), sc.clone(), 2)]
        );
        // The command line's later word is not the file's.
        assert_eq!(origins(&["-mesh", "x"]), [("e".into(), sc.clone(), 1)]);
        // m.msh is found two directories above the file.
        let h = hint_from("'scene' line 2", &sc, "m.msh");
        let base = std::fs::canonicalize(&d).unwrap();
        assert!(
            h.ends_with(&format!("'m.msh' is in {}: run there)", base.display())),
            "{h}"
        );
        assert!(
            h.starts_with(" (named in 'scene' line 2; paths are relative"),
            "{h}"
        );
        let h = hint_from("'scene' line 2", &sc, "nowhere.msh");
        assert!(
            !h.contains("run there") && h.contains("working directory"),
            "{h}"
        );
        // An absolute path or one found here: nothing to add.
        assert_eq!(hint_from("x", &sc, &sc), "");
        assert_eq!(hint_from("x", &sc, "Cargo.toml"), "");
        let _ = std::fs::remove_dir_all(&d);
    }

    /// Overrides the user probably did not mean are named (a file that
    /// overrides the command line written before it, one file giving an
    /// option twice), the usual ones are not (the command line or an
    /// including file over a file's option), and only an option's last
    /// override counts.
    #[test]
    fn surprising_overrides_are_named() {
        let d = dir("overrides");
        let (base, scene) = (d.join("base"), d.join("scene"));
        std::fs::write(&base, "-E 1\n-nu 0.3\n-ksp_type cg\n-ksp_type preonly\n").unwrap();
        let text = format!("-options_file {}\n-E 2\n-NU 0.3\n", base.display());
        std::fs::write(&scene, text).unwrap();
        let (b, sc) = (base.display().to_string(), scene.display().to_string());
        let run = |args: &[&str]| {
            let mut a = s(&["prog"]);
            a.extend(s(args));
            expand(&a, None, &[]).unwrap().overridden
        };
        let within = format!(
            "option -ksp_type is given twice: cg ('{b}' line 3), then preonly ('{b}' line 4); the later one, preonly, is used (PETSc's rule: the last one given wins)"
        );
        let usual = run(&["-options_file", &sc, "-E", "3", "-mesh", "m"]);
        assert_eq!(usual.len(), 1);
        assert_eq!(usual[0], within);
        let over = run(&["-E", "5", "-options_file", &sc, "-nu", "-0.5"]);
        assert_eq!(
            over,
            [
                within.clone(),
                format!("option -E is given twice: 5 (the command line), then 2 ('{sc}' line 2); the later one, 2, is used (PETSc's rule: the last one given wins)")
            ]
        );
        // Given again after the file: the command line's last word stands.
        let again = run(&["-E", "5", "-options_file", &sc, "-E", "5"]);
        assert_eq!(again, [within]);
        // The same value twice, a flag twice: nothing to say.
        let text = "-ubr_monitor\n-ubr_monitor\n-nu 0.3\n-nu 0.3\n";
        std::fs::write(&base, text).unwrap();
        assert!(run(&["-ubr_monitor", "-options_file", &b]).is_empty());
        let _ = std::fs::remove_dir_all(&d);
    }

    #[test]
    fn files_expand_in_place_in_order() {
        let d = dir("expand");
        let a = d.join("a");
        let b = d.join("b");
        std::fs::write(&b, "-E 1\n-nu 0.3 # comment\n").unwrap();
        std::fs::write(
            &a,
            format!(
                "\u{feff}# scene\n-options_file {}\n-mesh \"x y.msh\"\n\t-ubr_monitor\r\n",
                b.display()
            ),
        )
        .unwrap();
        let args = s(&[
            "prog",
            "-E",
            "5",
            "-options_file",
            a.to_str().unwrap(),
            "-nu",
            "0.2",
        ]);
        let e = expand(&args, None, &[]).unwrap();
        assert_eq!(
            e.args,
            s(&[
                "prog",
                "-E",
                "5",
                "-E",
                "1",
                "-nu",
                "0.3",
                "-mesh",
                "x y.msh",
                "-ubr_monitor",
                "-nu",
                "0.2"
            ])
        );
        assert_eq!(e.files.len(), 2);
        assert_eq!(e.env, None);
        let e = expand(
            &s(&["prog"]),
            Some(&format!("-options_file {} -x \"a b\"", b.display())),
            &[],
        )
        .unwrap();
        assert_eq!(e.env.as_deref(), Some("-E 1 -nu 0.3 -x \"a b\""));
        let _ = std::fs::remove_dir_all(&d);
    }

    #[test]
    fn cycles_are_named() {
        let d = dir("cycle");
        let a = d.join("a");
        let b = d.join("b");
        std::fs::write(&a, format!("-options_file {}\n", b.display())).unwrap();
        std::fs::write(&b, format!("-options_file {}\n", a.display())).unwrap();
        let e = expand(
            &s(&["prog", "-options_file", a.to_str().unwrap()]),
            None,
            &[],
        )
        .unwrap_err();
        assert!(e.contains("includes itself"), "{e}");
        assert!(
            e.contains(&format!(
                "{} -> {} -> {}",
                a.display(),
                b.display(),
                a.display()
            )),
            "{e}"
        );
        // The same file twice, not nested, is no cycle.
        std::fs::write(&b, "-E 1\n").unwrap();
        std::fs::write(
            &a,
            format!("-options_file {0}\n-options_file {0}\n", b.display()),
        )
        .unwrap();
        let e = expand(
            &s(&["prog", "-options_file", a.to_str().unwrap()]),
            None,
            &[],
        )
        .unwrap();
        assert_eq!(e.args, s(&["prog", "-E", "1", "-E", "1"]));
        let _ = std::fs::remove_dir_all(&d);
    }

    #[test]
    fn bad_lines_are_named() {
        let err = |text: &str| parse(text.as_bytes(), "f").unwrap_err();
        let e = err("-E 1\n-mesh /tmp/my dir/m.msh\n");
        assert!(
            e.contains("line 2") && e.contains("-mesh \"/tmp/my dir/m.msh\""),
            "{e}"
        );
        assert!(err("-E -nu").contains("two options"));
        assert!(err("-E 1 -nu 0.3").contains("two options on one line (-E -nu)"));
        assert!(err("E 1").contains("'E' is not an option"));
        assert!(err("-1x 3").contains("not an option name"));
        assert!(parse(&[0xFF, 0xFE, b'-'], "f")
            .unwrap_err()
            .contains("UTF-16"));
        let (lines, bom) = parse("\u{feff}-E 1\nalias -a -b\n".as_bytes(), "f").unwrap();
        assert!(bom);
        assert_eq!(lines.len(), 2);
    }
}
