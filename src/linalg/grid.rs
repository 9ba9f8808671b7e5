//! The Schur complement of the condensed back-end kept where MUMPS builds
//! it (`-ubr_schur_distributed 1`): each rank's column blocks of MUMPS' 1 x P
//! process grid (ICNTL(19) = 3, the complete matrix), factorized there by
//! ScaLAPACK's Cholesky (`pdpotrf`) and solved by `pdpotrs`, so that neither
//! the m^3/3 of the factorization nor the m^2 of every solve is rank 0's
//! alone. The right-hand side of a solve (m values) is gathered on rank 0,
//! which holds the grid's one column block of a vector, and its solution
//! scattered back from there, as on the host path.
//!
//! ScaLAPACK and its C BLACS interface are those MUMPS loaded (Debian's
//! `libscalapack-openmpi`, the library MUMPS' root and Schur complement
//! use), found by `dlsym`: the build links nothing more, and a MUMPS built
//! without ScaLAPACK (sequential) is told in words.

use super::direct::host_verdict;
use crate::comm::{allreduce_max, Layout};
use crate::error::Error;
use mpi::collective::SystemOperation;
use mpi::traits::*;
use std::ffi::{c_char, c_int, c_void, CStr};

/// A ScaLAPACK array descriptor (DESC_, 9 integers).
type Desc = [c_int; 9];

// SAFETY: a routine's type; every call through it states its contract.
type SysHandle = unsafe extern "C" fn(mpi::ffi::MPI_Comm) -> c_int;
// SAFETY: a routine's type; every call through it states its contract.
type GridInit = unsafe extern "C" fn(*mut c_int, *const c_char, c_int, c_int);
// SAFETY: a routine's type; every call through it states its contract.
type Release = unsafe extern "C" fn(c_int);
// SAFETY: a routine's type; every call through it states its contract.
type DescInit = unsafe extern "C" fn(
    *mut c_int,
    *const c_int,
    *const c_int,
    *const c_int,
    *const c_int,
    *const c_int,
    *const c_int,
    *const c_int,
    *const c_int,
    *mut c_int,
);
// SAFETY: a routine's type; every call through it states its contract.
type Potrf = unsafe extern "C" fn(
    *const c_char,
    *const c_int,
    *mut f64,
    *const c_int,
    *const c_int,
    *const c_int,
    *mut c_int,
);
// SAFETY: a routine's type; every call through it states its contract.
type Potrs = unsafe extern "C" fn(
    *const c_char,
    *const c_int,
    *const c_int,
    *const f64,
    *const c_int,
    *const c_int,
    *const c_int,
    *mut f64,
    *const c_int,
    *const c_int,
    *const c_int,
    *mut c_int,
);

/// The routines of BLACS and ScaLAPACK this module calls.
struct Api {
    sys_handle: SysHandle,
    grid_init: GridInit,
    grid_exit: Release,
    free_handle: Release,
    desc_init: DescInit,
    potrf: Potrf,
    potrs: Potrs,
}

/// The address of `name` in the process, or `None`.
fn symbol(name: &CStr) -> Option<*mut c_void> {
    let p = crate::dense::loaded_symbol(name);
    (!p.is_null()).then_some(p)
}

/// Whether the process loaded BLACS and ScaLAPACK (those of MUMPS): the
/// default layout of the Schur complement stays on rank 0 without them
/// (a MUMPS built without ScaLAPACK), where `-ubr_schur_distributed 1` is
/// refused.
pub fn scalapack_loaded() -> bool {
    Api::loaded().is_some()
}

impl Api {
    /// The routines, if the process loaded them (MUMPS' ScaLAPACK).
    fn loaded() -> Option<Api> {
        // SAFETY: each address is the named routine of the BLACS/ScaLAPACK
        // library MUMPS loaded, and each type is that routine's interface
        // (ScaLAPACK 2.2: the C BLACS functions take values, the Fortran
        // routines every argument by reference; CHARACTER*1 arguments are
        // read through their pointer, as LAPACK's are elsewhere here).
        unsafe {
            Some(Api {
                sys_handle: std::mem::transmute::<*mut c_void, SysHandle>(symbol(
                    c"Csys2blacs_handle",
                )?),
                grid_init: std::mem::transmute::<*mut c_void, GridInit>(symbol(
                    c"Cblacs_gridinit",
                )?),
                grid_exit: std::mem::transmute::<*mut c_void, Release>(symbol(c"Cblacs_gridexit")?),
                free_handle: std::mem::transmute::<*mut c_void, Release>(symbol(
                    c"Cfree_blacs_system_handle",
                )?),
                desc_init: std::mem::transmute::<*mut c_void, DescInit>(symbol(c"descinit_")?),
                potrf: std::mem::transmute::<*mut c_void, Potrf>(symbol(c"pdpotrf_")?),
                potrs: std::mem::transmute::<*mut c_void, Potrs>(symbol(c"pdpotrs_")?),
            })
        }
    }
}

/// The number of rows or columns of an order-`n` matrix that process `p`
/// of `procs` holds in blocks of `nb` (ScaLAPACK's NUMROC, first block on
/// process 0).
pub(super) fn numroc(n: usize, nb: usize, p: usize, procs: usize) -> usize {
    let blocks = n / nb;
    let mut count = (blocks / procs) * nb;
    let extra = blocks % procs;
    if p < extra {
        count += nb;
    } else if p == extra {
        count += n % nb;
    }
    count
}

const LOWER: c_char = b'L' as c_char;

/// The Schur complement S on the 1 x P grid: this rank's columns of its
/// Cholesky factors at the assembled r and, after a change of r, at the
/// current one. S itself stays in MUMPS' array (`raw` of the methods).
pub(super) struct GridSchur {
    api: Api,
    handle: c_int,
    ctx: c_int,
    m: usize,
    desc: Desc,
    desc_b: Desc,
    /// The global column of each local column.
    cols: Vec<usize>,
    assembled: Vec<f64>,
    shifted: Vec<f64>,
    shifted_on: bool,
    /// A right-hand side and its solution (rank 0's is the grid's vector).
    b: Vec<f64>,
    /// Whether this is rank 0.
    host: bool,
}

impl Drop for GridSchur {
    fn drop(&mut self) {
        // SAFETY: the context and the system handle made in `new`, each
        // released once; BLACS frees its own data only.
        unsafe {
            (self.api.grid_exit)(self.ctx);
            (self.api.free_handle)(self.handle);
        }
    }
}

/// `Err` on every rank when any rank's `bytes` (0: none) could not be
/// allocated.
fn memory_verdict<C: Communicator>(world: &C, m: usize, bytes: usize) -> Result<(), Error> {
    let worst = allreduce_max(world, bytes as f64);
    if worst > 0.0 {
        return Err(Error::OutOfMemory(format!(
            "a rank cannot allocate its part of the distributed Schur complement on the {m} contact unknowns ({:.1} MiB); -ubr_condense_max 0 solves without it",
            worst / (1u64 << 20) as f64
        )));
    }
    Ok(())
}

impl GridSchur {
    /// The grid of `world` (1 x P, rank p in process column p, as MUMPS'),
    /// and the factor of S (this rank's columns `raw`, m rows each,
    /// column-major, in blocks of `nb`).
    pub fn new<C: Communicator>(
        world: &C,
        comm: mpi::ffi::MPI_Comm,
        raw: &[f64],
        m: usize,
        nb: usize,
    ) -> Result<GridSchur, Error> {
        let api = Api::loaded();
        host_verdict(
            world,
            api.is_none().then(|| {
                Error::BadInput("-ubr_schur_distributed 1 needs ScaLAPACK, and the MUMPS this program loaded has none (a sequential MUMPS); use -ubr_schur_distributed 0".into())
            }),
        )?;
        let api = api.expect("checked on every rank");
        let (rank, procs) = (world.rank() as usize, world.size() as usize);
        let nloc = numroc(m, nb, rank, procs);
        let cols = (0..nloc)
            .map(|jl| (jl / nb) * procs * nb + rank * nb + jl % nb)
            .collect();
        // SAFETY: `comm` is a live communicator (MUMPS' own); the handle
        // and the context are plain integers BLACS returns.
        let (handle, ctx) = unsafe {
            let handle = (api.sys_handle)(comm);
            let mut ctx = handle;
            (api.grid_init)(&mut ctx, c"R".as_ptr(), 1, procs as c_int);
            (handle, ctx)
        };
        let mut grid = GridSchur {
            api,
            handle,
            ctx,
            m,
            desc: [0; 9],
            desc_b: [0; 9],
            cols,
            assembled: Vec::new(),
            shifted: Vec::new(),
            shifted_on: false,
            b: vec![0.0; m],
            host: rank == 0,
        };
        let ok = grid.describe(nb);
        let bad = allreduce_max(world, if ok { 0.0 } else { 1.0 });
        if bad > 0.0 {
            return Err(Error::Internal(
                "ScaLAPACK refused the descriptor of the distributed Schur complement".into(),
            ));
        }
        grid.refactor(world, raw)?;
        Ok(grid)
    }

    /// The descriptors of S (m x m) and of a vector (m x 1), in blocks of
    /// `nb`, leading dimension m (one process row holds every row).
    fn describe(&mut self, nb: usize) -> bool {
        let (m, nb, zero, ctx) = (self.m as c_int, nb as c_int, 0, self.ctx);
        let desc_init = self.api.desc_init;
        let init = |desc: &mut Desc, cols: c_int| {
            let mut info = 0;
            // SAFETY: a 9-integer descriptor, every other argument a live
            // integer (descinit_ reads them by reference).
            unsafe {
                desc_init(
                    desc.as_mut_ptr(),
                    &m,
                    &cols,
                    &nb,
                    &nb,
                    &zero,
                    &zero,
                    &ctx,
                    &m,
                    &mut info,
                )
            };
            info == 0
        };
        init(&mut self.desc, m) & init(&mut self.desc_b, 1)
    }

    /// The factor at the assembled r from `raw` (this rank's columns of S
    /// after a factorization); the factor at a shifted r is dropped.
    pub fn refactor<C: Communicator>(&mut self, world: &C, raw: &[f64]) -> Result<(), Error> {
        self.shifted_on = false;
        self.shifted = Vec::new();
        let mut a = std::mem::take(&mut self.assembled);
        let r = self.factor_into(world, &mut a, raw, |_| {});
        self.assembled = a;
        r
    }

    /// The factor of S + `delta` M, M the `d x d` blocks `blocks` of every
    /// candidate in the Schur order (row-major each; on every rank).
    pub fn shift<C: Communicator>(
        &mut self,
        world: &C,
        raw: &[f64],
        delta: f64,
        blocks: &[f64],
        d: usize,
    ) -> Result<(), Error> {
        let mut f = std::mem::take(&mut self.shifted);
        let cols = self.cols.clone();
        let m = self.m;
        let r = self.factor_into(world, &mut f, raw, |s| {
            for (jl, &j) in cols.iter().enumerate() {
                let (i, c) = (j / d, j % d);
                for a in 0..d {
                    s[jl * m + i * d + a] += delta * blocks[i * d * d + a * d + c];
                }
            }
        });
        self.shifted = f;
        self.shifted_on = r.is_ok();
        r
    }

    /// `raw` copied into `f`, `modify`d, factorized (collective).
    fn factor_into<C: Communicator>(
        &mut self,
        world: &C,
        f: &mut Vec<f64>,
        raw: &[f64],
        modify: impl FnOnce(&mut [f64]),
    ) -> Result<(), Error> {
        let len = self.cols.len() * self.m;
        f.clear();
        let short = crate::error::fallible(|| f.try_reserve_exact(len))
            .err()
            .map_or(0, |_| len * 8);
        memory_verdict(world, self.m, short)?;
        // Collective: a rank whose part is short makes every rank stop.
        if allreduce_max(world, if raw.len() < len { 1.0 } else { 0.0 }) > 0.0 {
            return Err(Error::Internal(
                "the distributed Schur complement's part is not the 1 x P grid's".into(),
            ));
        }
        f.extend_from_slice(&raw[..len]);
        modify(f);
        let (n, one, mut info) = (self.m as c_int, 1 as c_int, 0 as c_int);
        // SAFETY: `f` holds this rank's columns of the m x m matrix that
        // `desc` describes (NUMROC of them, m rows each, checked above);
        // collective on the grid, which every rank enters.
        unsafe {
            (self.api.potrf)(
                &LOWER,
                &n,
                f.as_mut_ptr(),
                &one,
                &one,
                self.desc.as_ptr(),
                &mut info,
            )
        };
        let k = allreduce_max(world, info as f64);
        if k != 0.0 {
            return Err(Error::LinearSolver(format!(
                "ScaLAPACK's Cholesky factorization of the Schur complement on the {} contact unknowns failed (INFO = {k}): the matrix K + r B^T W B is singular or nearly so",
                self.m
            )));
        }
        Ok(())
    }

    /// `x = S^{-1} c` (this rank's parts, `layout`), S at the assembled r
    /// or, when `current` and r changed, at the current one.
    pub fn solve<C: Communicator>(
        &mut self,
        world: &C,
        layout: &Layout,
        c: &[f64],
        x: &mut [f64],
        current: bool,
    ) -> Result<(), Error> {
        layout.gather_into(world, c, &mut self.b);
        self.solve_gathered(current)?;
        layout.scatter(world, &self.b, x);
        Ok(())
    }

    /// The solve of [`GridSchur::solve`] with the right-hand side already
    /// in rank 0's `b`, the solution left there.
    fn solve_gathered(&mut self, current: bool) -> Result<(), Error> {
        let f = if current && self.shifted_on {
            &self.shifted
        } else {
            &self.assembled
        };
        let (n, one, mut info) = (self.m as c_int, 1 as c_int, 0 as c_int);
        // SAFETY: `f` is the factor `desc` describes (pdpotrf's output), `b`
        // m values (the m x 1 vector of `desc_b`, rank 0's column block);
        // collective on the grid.
        unsafe {
            (self.api.potrs)(
                &LOWER,
                &n,
                &one,
                f.as_ptr(),
                &one,
                &one,
                self.desc.as_ptr(),
                self.b.as_mut_ptr(),
                &one,
                &one,
                self.desc_b.as_ptr(),
                &mut info,
            )
        };
        // INFO is an argument error only, and the same on every rank:
        // pdpotrs checks its arguments with PCHK2MAT, which reduces INFO
        // over the grid. No reduction of ours then, in every iteration.
        if info != 0 {
            return Err(Error::Internal(format!(
                "ScaLAPACK's solve with the Schur complement refused argument {}",
                -info
            )));
        }
        Ok(())
    }

    /// Solves with S at the assembled r each of the `k` columns of `red`,
    /// MUMPS' reduced right-hand sides (m values each, column-major; rank
    /// 0's are read and overwritten by the solutions, the other ranks' are
    /// unread and may be empty). Collective: every rank takes part in each
    /// column's solve.
    pub fn solve_reduced(&mut self, red: &mut [f64], k: usize) -> Result<(), Error> {
        let (m, host) = (self.m, self.host);
        for j in 0..k {
            if host {
                self.b.copy_from_slice(&red[j * m..(j + 1) * m]);
            }
            self.solve_gathered(false)?;
            if host {
                red[j * m..(j + 1) * m].copy_from_slice(&self.b);
            }
        }
        Ok(())
    }

    /// `S_a y` for this rank's part `y` (`layout`) into `out`: every rank
    /// multiplies its columns of S (`raw`), the products summed on rank 0.
    pub fn apply<C: Communicator>(
        &self,
        world: &C,
        layout: &Layout,
        raw: &[f64],
        y: &[f64],
        out: &mut [f64],
    ) {
        let m = self.m;
        let all = layout.all_gather(world, y);
        let mut part = vec![0.0; m];
        for (jl, &j) in self.cols.iter().enumerate() {
            let yj = all[j];
            for (p, s) in part.iter_mut().zip(&raw[jl * m..(jl + 1) * m]) {
                *p += s * yj;
            }
        }
        let root = world.process_at_rank(0);
        let mut sum = vec![0.0; if world.rank() == 0 { m } else { 0 }];
        if world.rank() == 0 {
            root.reduce_into_root(&part[..], &mut sum[..], SystemOperation::sum());
        } else {
            root.reduce_into(&part[..], SystemOperation::sum());
        }
        layout.scatter(world, &sum, out);
    }
}
