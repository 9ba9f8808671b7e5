//! The options database, read as strings and parsed by the caller so that
//! errors name the option.

use super::{check, strings_from, sys};
use crate::error::Error;
use std::cell::RefCell;
use std::ffi::{c_char, c_void, CStr, CString};

fn cname(name: &str) -> CString {
    CString::new(name).expect("option names have no NUL")
}

/// The raw string value of `-name`, `Some("")` when given without a value.
pub fn get_string(name: &str) -> Result<Option<String>, Error> {
    let key = cname(name);
    let mut buf = vec![0 as c_char; 4096];
    let mut set = sys::PETSC_FALSE;
    // SAFETY: `key` is a C string; PETSc writes at most buf.len() bytes, a
    // NUL included, into buf and one bool into `set` (the global database,
    // no prefix: the null pointers).
    check(unsafe {
        sys::PetscOptionsGetString(
            std::ptr::null_mut(),
            std::ptr::null(),
            key.as_ptr(),
            buf.as_mut_ptr(),
            buf.len(),
            &mut set,
        )
    })?;
    if set == sys::PETSC_FALSE {
        return Ok(None);
    }
    let bytes: Vec<u8> = buf.iter().map(|&c| c as u8).collect();
    let s = CStr::from_bytes_until_nul(&bytes).unwrap_or_default();
    Ok(Some(s.to_string_lossy().into_owned()))
}

pub fn has_name(name: &str) -> Result<bool, Error> {
    let key = cname(name);
    let mut set = sys::PETSC_FALSE;
    // SAFETY: `key` is a C string; PETSc writes one bool into `set`.
    check(unsafe {
        sys::PetscOptionsHasName(
            std::ptr::null_mut(),
            std::ptr::null(),
            key.as_ptr(),
            &mut set,
        )
    })?;
    Ok(set == sys::PETSC_TRUE)
}

thread_local! {
    /// The options the program set itself ([`set_default`]): not the
    /// user's, so never reported as unused.
    static SET_BY_PROGRAM: RefCell<Vec<String>> = const { RefCell::new(Vec::new()) };
}

/// Sets `-name value` unless the user already set `-name`.
pub fn set_default(name: &str, value: &str) -> Result<(), Error> {
    if has_name(name)? {
        return Ok(());
    }
    SET_BY_PROGRAM.with(|s| s.borrow_mut().push(name.to_string()));
    let key = cname(name);
    let val = cname(value);
    // SAFETY: two C strings, which PETSc copies.
    check(unsafe { sys::PetscOptionsSetValue(std::ptr::null_mut(), key.as_ptr(), val.as_ptr()) })
}

/// The options of the database that nothing has read so far (names with
/// their leading `-`), leaving out those the program set itself.
pub fn unused() -> Result<Vec<String>, Error> {
    let mut out = left_in(std::ptr::null_mut())?;
    let ours = SET_BY_PROGRAM.with(|s| s.borrow().clone());
    out.retain(|name| !ours.contains(name));
    Ok(out)
}

/// The options of database `db` (null: the global one; else a live
/// database) that nothing has read (names with their leading `-`).
pub(super) fn left_in(db: sys::PetscOptions) -> Result<Vec<String>, Error> {
    let mut n: sys::PetscInt = 0;
    let mut names: *mut *mut c_char = std::ptr::null_mut();
    let mut values: *mut *mut c_char = std::ptr::null_mut();
    // SAFETY: `db` is null or live (the contract above); PETSc writes the
    // count and two arrays of its own, given back below.
    check(unsafe { sys::PetscOptionsLeftGet(db, &mut n, &mut names, &mut values) })?;
    // SAFETY: `names` holds n pointers, each null or a C string, valid until
    // the restore below.
    let names_read = unsafe { strings_from(names as *const *const c_char, n.max(0) as usize) };
    let out = names_read
        .iter()
        // (PETSc keeps a name without its leading dash: `--E` as `-E`.)
        .map(|name| format!("-{name}"))
        .collect();
    // SAFETY: gives back the arrays PETSc made above, once.
    check(unsafe { sys::PetscOptionsLeftRestore(db, &mut n, &mut names, &mut values) })?;
    Ok(out)
}

/// The whole database as PETSc lists it (`-name value ...`), each error
/// code through `check`.
pub(super) fn listing<E>(
    check: impl Fn(sys::PetscErrorCode) -> Result<(), E>,
) -> Result<CString, E> {
    let mut ptr: *mut c_char = std::ptr::null_mut();
    // SAFETY: PETSc allocates the listing and writes its address into ptr.
    check(unsafe { sys::PetscOptionsGetAll(std::ptr::null_mut(), &mut ptr) })?;
    // SAFETY: the C string PETSc just made.
    let all = unsafe { CStr::from_ptr(ptr) }.to_owned();
    // SAFETY: PETSc allocated it (PetscMalloc) for us; freed once, here.
    check(unsafe { sys::ubr_free(ptr as *mut c_void) })?;
    Ok(all)
}

/// Every option of the database with its value (None: given without
/// one), without marking any as used. (A value with a space reads as
/// its first word: PETSc's listing does not quote it.)
pub fn all_pairs() -> Result<Vec<(String, Option<String>)>, Error> {
    let all = listing(check)?.to_string_lossy().into_owned();
    let words: Vec<&str> = all.split_whitespace().collect();
    let mut out: Vec<(String, Option<String>)> = Vec::new();
    for w in words {
        if is_key(w) {
            out.push((w.to_string(), None));
        } else if let Some((_, v @ None)) = out.last_mut() {
            *v = Some(w.to_string());
        }
    }
    Ok(out)
}

/// The value of `-name` as [`get_string`] gives it (`Some("")` when given
/// without a value), without marking the option used: for the checks of
/// options that the run may not read at all, which must still be named
/// unused then (`-mat_mumps_icntl_7` in a run without MUMPS).
pub fn peek(name: &str) -> Result<Option<String>, Error> {
    Ok(all_pairs()?
        .into_iter()
        .rev()
        .find(|(n, _)| n.eq_ignore_ascii_case(name))
        .map(|(_, v)| v.unwrap_or_default()))
}

/// The names of every option in the database (with their leading `-`).
pub fn all_names() -> Result<Vec<String>, Error> {
    let all = listing(check)?.to_string_lossy().into_owned();
    Ok(all
        .split_whitespace()
        .filter(|t| t.starts_with('-') && t.len() > 1 && t.parse::<f64>().is_err())
        .map(|t| t.to_string())
        .collect())
}

/// PETSc's `PetscOptionsValidKey`: `-` then a letter, and not a number
/// (`-inf`, `-nan`).
pub fn is_key(s: &str) -> bool {
    let k = match s.strip_prefix("--") {
        Some(rest) => rest,
        None => match s.strip_prefix('-') {
            Some(rest) => rest,
            None => return false,
        },
    };
    if !k.starts_with(|c: char| c.is_ascii_alphabetic()) {
        return false;
    }
    let lower = k.to_ascii_lowercase();
    for number in ["infinity", "inf", "nan"] {
        if let Some(after) = lower.strip_prefix(number) {
            return after.starts_with(|c: char| c == '_' || c.is_ascii_alphanumeric());
        }
    }
    true
}

#[cfg(test)]
mod tests {
    use crate::petsc::{string_from, strings_from};

    // string_from reads a C string; strings_from skips null entries.
    #[test]
    fn c_strings_are_read_and_nulls_skipped() {
        let a = c"-ksp_type";
        let ptrs = [a.as_ptr(), std::ptr::null(), c"cg".as_ptr()];
        // SAFETY: three pointers, each null or a static C string.
        let got = unsafe { strings_from(ptrs.as_ptr(), ptrs.len()) };
        assert_eq!(got, vec!["-ksp_type".to_string(), "cg".to_string()]);
        // SAFETY: null is allowed.
        assert_eq!(unsafe { string_from(std::ptr::null()) }, "");
    }
}
