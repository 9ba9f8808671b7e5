//! The house rules of `src/` (issue 25, "Acceptance"), checked on the
//! source text so that a new violation fails the suite:
//! - no module imports a module of a higher floor (the floors are listed
//!   in `src/lib.rs`, and in [`FLOORS`] here);
//! - no file over 900 lines, except the Gmsh reader;
//! - no function over 120 lines (from its `fn` line to the closing brace
//!   at the same indent);
//! - as many `SAFETY:` comments as lines with `unsafe` code.
//!
//! Where another part of the tree still breaks a rule, it is named in a
//! known-exception list below: the test passes with it and fails on any new
//! violation, and on an exception that no longer applies (so that the list
//! only shrinks).

use std::collections::BTreeSet;
use std::fs;
use std::path::{Path, PathBuf};

/// The floors, bottom to top: a module may import its own floor and those
/// below. Keep in step with the module documentation of `src/lib.rs`.
const FLOORS: &[&[&str]] = &[
    &["error", "petsc", "mumps", "dense", "comm", "progress"],
    &["options"],
    &["element"],
    &["mesh"],
    &["fem"],
    &["contact"],
    &["linalg"],
    &["wellposed", "touching"],
    &["solver"],
    &["checks"],
    &["report"],
    &["app"],
    &["lib", "main"],
];

/// Upward imports allowed: none (the list stays, so that an exception
/// can only be added in the open, with its reason).
const KNOWN_UPWARD: &[(&str, &str)] = &[];

/// Files allowed over [`MAX_FILE_LINES`]: the Gmsh reader (by the issue).
const KNOWN_LONG_FILES: &[&str] = &["src/mesh/gmsh.rs"];

/// Functions allowed over [`MAX_FN_LINES`]: none.
const KNOWN_LONG_FNS: &[(&str, &str)] = &[];

const MAX_FILE_LINES: usize = 900;
const MAX_FN_LINES: usize = 120;

fn src_files() -> Vec<PathBuf> {
    fn walk(dir: &Path, out: &mut Vec<PathBuf>) {
        for entry in fs::read_dir(dir).expect("read src/") {
            let path = entry.expect("a directory entry").path();
            if path.is_dir() {
                walk(&path, out);
            } else if path.extension().is_some_and(|e| e == "rs") {
                out.push(path);
            }
        }
    }
    let mut out = Vec::new();
    walk(&Path::new(env!("CARGO_MANIFEST_DIR")).join("src"), &mut out);
    out.sort();
    out
}

/// `src/...` of a file, with forward slashes.
fn rel(path: &Path) -> String {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let r = path.strip_prefix(root).expect("under the crate");
    r.to_string_lossy().replace('\\', "/")
}

/// The top-level module a file belongs to (`src/solver/ubr.rs`: `solver`).
fn module_of(rel: &str) -> String {
    let inner = rel.strip_prefix("src/").expect("a file of src/");
    let first = inner.split('/').next().expect("a path");
    first.trim_end_matches(".rs").to_string()
}

fn floor(module: &str) -> Option<usize> {
    FLOORS.iter().position(|f| f.contains(&module))
}

/// The line without its `//` comment (a line comment or doc comment; the
/// code has no `//` inside string literals on lines that import).
fn code(line: &str) -> &str {
    match line.find("//") {
        Some(i) => &line[..i],
        None => line,
    }
}

fn ident(s: &str) -> String {
    s.trim_start()
        .chars()
        .take_while(|c| c.is_alphanumeric() || *c == '_')
        .collect()
}

/// The top-level modules a file's code names: `crate::x`, `crate::{x, y}`,
/// and `super::x` where `super` is the crate root (files directly in
/// `src/` and `mod.rs` files one level down).
fn imported_modules(rel: &str, text: &str) -> BTreeSet<String> {
    let depth = rel.matches('/').count(); // src/x.rs: 1; src/x/y.rs: 2
    let super_is_root = depth == 1 || (depth == 2 && rel.ends_with("/mod.rs"));
    let mut out = BTreeSet::new();
    let mut prefixes = vec!["crate::"];
    if super_is_root {
        prefixes.push("super::");
    }
    for line in text.lines() {
        let line = code(line);
        for prefix in &prefixes {
            let mut rest = line;
            while let Some(i) = rest.find(prefix) {
                // Not the tail of a longer path (`foo::crate::` cannot occur;
                // `self::super::` would be rare): the prefix itself.
                let before = rest[..i].chars().last();
                rest = &rest[i + prefix.len()..];
                if before.is_some_and(|c| c.is_alphanumeric() || c == '_') {
                    continue;
                }
                if let Some(group) = rest.strip_prefix('{') {
                    // One level of a grouped import: the first name of each item.
                    let end = group.find('}').unwrap_or(group.len());
                    let mut level = 0;
                    let mut start = 0;
                    let items = &group[..end];
                    for (k, ch) in items.char_indices() {
                        match ch {
                            '{' => level += 1,
                            '}' => level -= 1,
                            ',' if level == 0 => {
                                out.insert(ident(&items[start..k]));
                                start = k + 1;
                            }
                            _ => {}
                        }
                    }
                    out.insert(ident(&items[start..]));
                } else {
                    out.insert(ident(rest));
                }
            }
        }
    }
    out.retain(|m| !m.is_empty() && m != "self" && floor(m).is_some());
    out
}

#[test]
fn no_module_imports_a_higher_floor() {
    let mut found = Vec::new();
    for path in src_files() {
        let rel = rel(&path);
        let module = module_of(&rel);
        let own = floor(&module).unwrap_or_else(|| {
            panic!("{rel}: module {module} has no floor: add it to FLOORS and to src/lib.rs")
        });
        let text = fs::read_to_string(&path).expect("read a source file");
        for m in imported_modules(&rel, &text) {
            let theirs = floor(&m).expect("retained");
            if theirs > own {
                found.push((rel.clone(), m));
            }
        }
    }
    let known: Vec<(String, String)> = KNOWN_UPWARD
        .iter()
        .map(|&(f, m)| (f.to_string(), m.to_string()))
        .collect();
    let new: Vec<_> = found.iter().filter(|v| !known.contains(v)).collect();
    assert!(
        new.is_empty(),
        "imports from a lower floor to a higher one (file, module): {new:?}"
    );
    let gone: Vec<_> = known.iter().filter(|k| !found.contains(k)).collect();
    assert!(
        gone.is_empty(),
        "known exceptions that no longer apply, remove them from KNOWN_UPWARD: {gone:?}"
    );
}

#[test]
fn no_file_over_900_lines() {
    let mut long = Vec::new();
    for path in src_files() {
        let rel = rel(&path);
        let lines = fs::read_to_string(&path).expect("read").lines().count();
        if lines > MAX_FILE_LINES {
            long.push((rel, lines));
        }
    }
    let new: Vec<_> = long
        .iter()
        .filter(|(f, _)| !KNOWN_LONG_FILES.contains(&f.as_str()))
        .collect();
    assert!(new.is_empty(), "files over {MAX_FILE_LINES} lines: {new:?}");
    let gone: Vec<_> = KNOWN_LONG_FILES
        .iter()
        .filter(|k| **k != "src/mesh/gmsh.rs" && !long.iter().any(|(f, _)| f == *k))
        .collect();
    assert!(
        gone.is_empty(),
        "files no longer over {MAX_FILE_LINES} lines, remove them from KNOWN_LONG_FILES: {gone:?}"
    );
}

/// (name, first line, lines) of every function with a body, from its `fn`
/// line to the closing brace at the same indent.
fn functions(text: &str) -> Vec<(String, usize, usize)> {
    let lines: Vec<&str> = text.lines().collect();
    let mut out = Vec::new();
    for (i, line) in lines.iter().enumerate() {
        let text = code(line);
        let trimmed = text.trim_start();
        let indent = &text[..text.len() - trimmed.len()];
        let Some(at) = fn_keyword(trimmed) else {
            continue;
        };
        let name = ident(&trimmed[at + 3..]);
        if name.is_empty() {
            continue;
        }
        // A one-line function, or a declaration without a body.
        let mut end = None;
        for (j, l) in lines.iter().enumerate().skip(i) {
            let c = code(l).trim_end();
            if j == i && c.ends_with('}') && c.contains('{') {
                end = Some(j);
                break;
            }
            if c.ends_with(';') && !lines[i..j].iter().any(|l| code(l).contains('{')) {
                break; // `fn f();` in a trait or extern block
            }
            if j > i && c == format!("{indent}}}") {
                end = Some(j);
                break;
            }
        }
        if let Some(end) = end {
            out.push((name, i + 1, end - i + 1));
        }
    }
    out
}

/// Where the `fn` keyword of an item starts in a trimmed line (after `pub`,
/// `pub(crate)`, `const`, `async`, `unsafe`, `extern "C"`).
fn fn_keyword(trimmed: &str) -> Option<usize> {
    let mut s = trimmed;
    let mut at = 0;
    loop {
        if s.starts_with("fn ") {
            return Some(at);
        }
        let skip = if s.starts_with("pub(") {
            s.find(')')? + 1
        } else if let Some(w) = ["pub ", "const ", "async ", "unsafe ", "extern \"C\" "]
            .iter()
            .find(|w| s.starts_with(**w))
        {
            w.len()
        } else {
            return None;
        };
        at += skip;
        s = &s[skip..];
        let t = s.trim_start();
        at += s.len() - t.len();
        s = t;
    }
}

#[test]
fn no_function_over_120_lines() {
    let (mut long, mut known_found) = (Vec::new(), Vec::new());
    for path in src_files() {
        let rel = rel(&path);
        let text = fs::read_to_string(&path).expect("read");
        for (name, line, n) in functions(&text) {
            if n <= MAX_FN_LINES {
                continue;
            }
            if KNOWN_LONG_FNS.contains(&(rel.as_str(), name.as_str())) {
                known_found.push((rel.clone(), name));
            } else {
                long.push(format!("{rel}:{line} fn {name}: {n} lines"));
            }
        }
    }
    assert!(
        long.is_empty(),
        "functions over {MAX_FN_LINES} lines:\n{}",
        long.join("\n")
    );
    let gone: Vec<_> = KNOWN_LONG_FNS
        .iter()
        .filter(|(f, n)| !known_found.iter().any(|(kf, kn)| kf == f && kn == n))
        .collect();
    assert!(
        gone.is_empty(),
        "functions no longer over {MAX_FN_LINES} lines, remove them from KNOWN_LONG_FNS: {gone:?}"
    );
}

#[test]

fn every_unsafe_has_a_safety_comment() {
    let (mut unsafe_lines, mut safety) = (0, 0);
    for path in src_files() {
        let text = fs::read_to_string(&path).expect("read");
        for line in text.lines() {
            if line.contains("SAFETY:") {
                safety += 1;
            }
            // As the acceptance counts them (`grep -c unsafe`):
            // every line with the word, lint names and comments included.
            if line.contains("unsafe") {
                unsafe_lines += 1;
            }
        }
    }
    assert_eq!(
        unsafe_lines, safety,
        "lines with `unsafe` code against `SAFETY:` comments"
    );
}

/// The checks themselves: they must be able to fail.
#[test]
fn the_checks_find_what_they_look_for() {
    let m = imported_modules(
        "src/mesh/mod.rs",
        "use crate::{error::Error, report::x};\nuse super::y; // crate::app\nlet a = crate::solver::f();",
    );
    let m: Vec<&str> = m.iter().map(String::as_str).collect();
    assert_eq!(m, ["error", "report", "solver"]);
    let top = imported_modules("src/options.rs", "use super::app;");
    assert!(top.contains("app"));
    let text = "pub fn a() {\n    x;\n}\nfn b() -> u8 { 1 }\n    pub(crate) fn c(\n        y: u8,\n    ) {\n    }\nfn d();\n";
    let f = functions(text);
    assert_eq!(
        f,
        [
            ("a".to_string(), 1, 3),
            ("b".to_string(), 4, 1),
            ("c".to_string(), 5, 4)
        ]
    );
}
