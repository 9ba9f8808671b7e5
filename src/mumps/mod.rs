//! MUMPS 5.5 through its own C interface (`dmumps_c`), where PETSc's
//! wrapper stops: a user ordering (METIS nested dissection as PERM_IN), and
//! the Schur complement on any number of ranks (centralized on the host).
//!
//! [`Mumps`] owns one MUMPS instance (JOB = -1 on creation, -2 on drop) and
//! the arrays it points into. Every call is checked: a negative INFOG(1)
//! becomes an [`Error`] with MUMPS' code and its meaning.
//!
//! Soundness: MUMPS reads and writes the arrays that the instance's
//! structure points to, during `dmumps_c` only. Every such pointer is set
//! by a method here to an array that [`Mumps`] owns (or, during a solve,
//! holds) and does not resize until the pointer is set again, so each call
//! of `dmumps_c` finds them valid for the sizes the structure states.

// Generated code: no lint of ours applies (its Default impls, for one, are
// blocks without comments).
#[allow(
    non_camel_case_types,
    non_snake_case,
    non_upper_case_globals,
    dead_code,
    clippy::all,
    clippy::restriction
)]
pub mod sys {
    include!(concat!(env!("OUT_DIR"), "/mumps_sys.rs"));
}

use crate::error::Error;

/// ICNTL(i), INFOG(i), ... are 1-based in MUMPS' manual.
macro_rules! icntl {
    ($id:expr, $i:expr) => {
        $id.icntl[$i - 1]
    };
}

/// The ICNTL entries the direct back-end (`linalg/direct.rs`) sets itself:
/// the input (5, 18), the Schur complement (19, 26), the right-hand sides
/// and solutions (20, 21); `-mat_mumps_icntl_N` does not reach them.
pub const OWNED_ICNTL: [usize; 6] = [5, 18, 19, 20, 21, 26];

/// What a negative INFOG(1) means (MUMPS 5.5 user guide, section 8).
pub(crate) fn meaning(code: i32, info2: i32) -> String {
    match code {
        -1 => format!("an error on rank {info2}"),
        -2 => format!("NNZ out of range ({info2})"),
        -3 => "called with an invalid JOB".to_string(),
        -5 | -7 | -13 => format!("could not allocate memory ({info2})"),
        -6 => format!("the matrix is structurally singular (rank {info2})"),
        -8 | -9 | -14 | -15 | -11 | -12 => {
            format!("the work space is too small ({info2}); raise ICNTL(14)")
        }
        -10 => format!("the matrix is numerically singular ({info2} pivots)"),
        -16 => format!("N out of range ({info2})"),
        -17 | -20 => "an internal communication buffer is too small; raise ICNTL(14)".to_string(),
        -22 => format!("an array is not allocated or too small (argument {info2})"),
        -19 => format!("the factorization needs more memory on a rank than ICNTL(23) (-mat_mumps_icntl_23) allows (INFO(2) = {info2})"),
        -38 => "a parallel analysis (ICNTL(28) = 2) needs PT-Scotch or ParMETIS, which this MUMPS was built without".to_string(),
        -39 => "the parallel analysis (ICNTL(28) = 2) cannot be used with a Schur complement".to_string(),
        -40 => "the matrix was declared positive definite but a negative pivot was met".to_string(),
        _ => format!("INFO(2) = {info2}"),
    }
}

/// One MUMPS instance on a communicator.
pub struct Mumps {
    id: Box<sys::DMUMPS_STRUC_C>,
    pub host: bool,
    // The arrays MUMPS points into (kept alive and unmoved while it may read them).
    irn: Vec<i32>,
    jcn: Vec<i32>,
    a: Vec<f64>,
    perm_in: Vec<i32>,
    listvar: Vec<i32>,
    schur: Vec<f64>,
    rhs: Vec<f64>,
    redrhs: Vec<f64>,
}

impl Drop for Mumps {
    fn drop(&mut self) {
        self.id.job = -2;
        // SAFETY: the instance made by JOB = -1 in `new` (MPI still runs:
        // a Mumps lives inside main's scope of rsmpi's universe), ended
        // once; JOB = -2 frees MUMPS' own data and reads none of ours.
        unsafe { sys::dmumps_c(&mut *self.id) };
    }
}

impl Mumps {
    /// A MUMPS instance on `comm` (JOB = -1), symmetric positive definite
    /// (`spd`, SYM = 1) or general symmetric (SYM = 2), the host working
    /// (PAR = 1), silent.
    pub fn new(comm: mpi::ffi::MPI_Comm, rank: i32, spd: bool) -> Result<Mumps, Error> {
        // Every field zero (bindgen's Default): null pointers, no sizes.
        let mut id: Box<sys::DMUMPS_STRUC_C> = Box::default();
        id.sym = if spd { 1 } else { 2 };
        id.par = 1;
        id.job = -1;
        // SAFETY: `comm` is a live communicator (the caller's); returns its
        // Fortran handle.
        id.comm_fortran = unsafe { mpi::ffi::MPI_Comm_c2f(comm) };
        // SAFETY: a structure of ours, its pointers null; JOB = -1 reads
        // SYM, PAR and COMM and sets the defaults.
        unsafe { sys::dmumps_c(&mut *id) };
        let mut m = Mumps {
            id,
            host: rank == 0,
            irn: Vec::new(),
            jcn: Vec::new(),
            a: Vec::new(),
            perm_in: Vec::new(),
            listvar: Vec::new(),
            schur: Vec::new(),
            rhs: Vec::new(),
            redrhs: Vec::new(),
        };
        m.check("initialization")?;
        // No output (ICNTL(1..3) streams off, ICNTL(4) level 0).
        icntl!(m.id, 1) = -1;
        icntl!(m.id, 2) = -1;
        icntl!(m.id, 3) = -1;
        icntl!(m.id, 4) = 0;
        Ok(m)
    }

    fn check(&self, phase: &str) -> Result<(), Error> {
        let code = self.id.infog[0];
        // -135 with INFOG(2) = -13: the static mapping of the analysis
        // could not allocate its work space.
        let mapping = code == -135 && self.id.infog[1] == -13;
        if mapping {
            return Err(Error::OutOfMemory(format!(
                "MUMPS {phase} could not allocate the work space of its mapping on one rank (INFOG(1) = -135, INFOG(2) = -13); give each rank more memory, or use more ranks"
            )));
        }
        if matches!(code, -5 | -7 | -13 | -19) {
            // INFOG(1) is the same on every rank (MUMPS ends a phase
            // collectively): so is this error.
            return Err(Error::OutOfMemory(self.memory_failure(phase, code)));
        }
        if code < 0 {
            return Err(Error::LinearSolver(format!(
                "MUMPS {phase} failed: INFOG(1) = {code}, {}",
                meaning(code, self.id.infog[1])
            )));
        }
        Ok(())
    }

    /// The message of a failed allocation (INFOG(1) = -5, -7, -13), or of
    /// a factorization that needs more than ICNTL(23) MB (-19): what MUMPS
    /// could not allocate or lacks (INFOG(2) entries, real ones or integers
    /// (-7), or millions of them when negative) and what its analysis
    /// predicted the factorization needs (INFOG(16), INFOG(17): MB per rank
    /// at most, in all).
    fn memory_failure(&self, phase: &str, code: i32) -> String {
        let info2 = self.id.infog[1] as f64;
        let entries = if info2 < 0.0 { -info2 * 1e6 } else { info2 };
        let bytes = if code == -7 { 4.0 } else { 8.0 };
        let mib = entries * bytes / (1u64 << 20) as f64;
        let mut msg = if code == -19 {
            format!(
                "MUMPS {phase} needs {mib:.1} MiB more on one rank than the {} MB a rank may use (ICNTL(23), -mat_mumps_icntl_23; INFOG(1) = -19)",
                icntl!(self.id, 23)
            )
        } else {
            format!("MUMPS {phase} could not allocate {mib:.1} MiB on one rank (INFOG(1) = {code})")
        };
        let (per_rank, total) = (self.id.infog[15], self.id.infog[16]);
        if per_rank > 0 {
            msg.push_str(&format!(
                "; its analysis predicted {per_rank} MB on the largest rank, {total} MB in all"
            ));
        }
        msg.push_str("; give each rank more memory, or use more ranks");
        msg
    }

    /// Sets ICNTL(i) (1-based).
    pub fn set_icntl(&mut self, i: usize, v: i32) {
        self.id.icntl[i - 1] = v;
    }

    pub fn icntl(&self, i: usize) -> i32 {
        self.id.icntl[i - 1]
    }

    /// Lets the analysis split large fronts into chains of smaller ones
    /// (KEEP(210) = 1: MUMPS' pre-splitting, which it otherwise does only
    /// out of core). A front whose master would factorize its pivot block
    /// while its slaves wait for the panels becomes a chain whose upper
    /// parts the slaves of the lower ones update (the flops are unchanged).
    pub fn split_fronts(&mut self) {
        self.id.keep[209] = 1;
    }

    /// KEEP(61): the fronts the analysis split (after [`Self::split_fronts`]).
    pub fn fronts_split(&self) -> i32 {
        self.id.keep[60]
    }

    /// Sets CNTL(i) (1-based).
    pub fn set_cntl(&mut self, i: usize, v: f64) {
        self.id.cntl[i - 1] = v;
    }

    /// RINFOG(i) (1-based): e.g. 1 the flops of the elimination... (3: of the factorization).
    pub fn rinfog(&self, i: usize) -> f64 {
        self.id.rinfog[i - 1]
    }

    /// INFOG(i) (1-based).
    pub fn infog(&self, i: usize) -> i32 {
        self.id.infog[i - 1]
    }

    /// INFO(i) (1-based): this rank's.
    pub fn info(&self, i: usize) -> i32 {
        self.id.info[i - 1]
    }

    /// The distributed assembled matrix (ICNTL(18) = 3, ICNTL(5) = 0): this
    /// rank's entries, 1-based, one triangle for a symmetric matrix
    /// (duplicates are summed); `n` the global order.
    pub fn set_matrix(&mut self, n: usize, irn: Vec<i32>, jcn: Vec<i32>, a: Vec<f64>) {
        assert!(irn.len() == jcn.len() && jcn.len() == a.len());
        self.irn = irn;
        self.jcn = jcn;
        self.a = a;
        icntl!(self.id, 5) = 0;
        icntl!(self.id, 18) = 3;
        self.id.n = n as i32;
        self.id.nnz_loc = self.a.len() as i64;
        self.id.nz_loc = self.a.len() as i32;
        self.id.irn_loc = self.irn.as_mut_ptr();
        self.id.jcn_loc = self.jcn.as_mut_ptr();
        self.id.a_loc = self.a.as_mut_ptr();
    }

    /// New values of the same entries (a refactorization).
    pub fn values_mut(&mut self) -> &mut [f64] {
        &mut self.a
    }

    /// The pivot order on the host: `perm_in[i]` is the position (1-based)
    /// of variable i + 1 (ICNTL(7) = 1, with the sequential analysis,
    /// ICNTL(28) = 1). Ignored on the other ranks.
    pub fn set_ordering(&mut self, perm_in: Vec<i32>) {
        icntl!(self.id, 7) = 1;
        icntl!(self.id, 28) = 1;
        self.perm_in = perm_in;
        if self.host {
            self.id.perm_in = self.perm_in.as_mut_ptr();
        }
    }

    /// Asks for the Schur complement on the variables `listvar` (1-based;
    /// on the host), returned centralized on the host by rows (ICNTL(19) = 1;
    /// for a symmetric matrix its lower triangle). `Err`: the host cannot
    /// allocate its `size x size` array (the bytes asked for); nothing is
    /// set then.
    pub fn set_schur(&mut self, size: usize, listvar: Vec<i32>) -> Result<(), usize> {
        if self.host {
            assert_eq!(listvar.len(), size);
            self.schur = crate::dense::try_zeros(size * size)?;
        }
        icntl!(self.id, 19) = 1;
        self.id.size_schur = size as i32;
        if self.host {
            self.listvar = listvar;
            self.id.listvar_schur = self.listvar.as_mut_ptr();
            self.id.schur = self.schur.as_mut_ptr();
            self.id.schur_lld = size as i32;
        }
        Ok(())
    }

    /// Asks for the Schur complement on `listvar` (1-based; on the host)
    /// distributed over every rank, the complete matrix (ICNTL(19) = 3) on
    /// a 1 x P process grid in column blocks of `block` (ScaLAPACK's 2D
    /// block-cyclic layout with one process row): the root front that holds
    /// it is then assembled by every rank rather than by one. Each rank's
    /// local array is sized after the analysis ([`Mumps::size_distributed_schur`]).
    pub fn set_distributed_schur(
        &mut self,
        size: usize,
        listvar: Vec<i32>,
        ranks: usize,
        block: usize,
    ) {
        icntl!(self.id, 19) = 3;
        self.id.size_schur = size as i32;
        self.id.nprow = 1;
        self.id.npcol = ranks as i32;
        self.id.mblock = block as i32;
        self.id.nblock = block as i32;
        if self.host {
            assert_eq!(listvar.len(), size);
            self.listvar = listvar;
            self.id.listvar_schur = self.listvar.as_mut_ptr();
        }
    }

    /// After the analysis: this rank's part of a distributed Schur
    /// complement, `(rows, columns)` (SCHUR_MLOC, SCHUR_NLOC), allocated
    /// and given to MUMPS. `Err`: the bytes it could not allocate.
    pub fn size_distributed_schur(&mut self) -> Result<(usize, usize), usize> {
        let (mloc, nloc) = (
            self.id.schur_mloc.max(0) as usize,
            self.id.schur_nloc.max(0) as usize,
        );
        let lld = mloc.max(1);
        self.schur = crate::dense::try_zeros(lld * nloc.max(1))?;
        self.id.schur = self.schur.as_mut_ptr();
        self.id.schur_lld = lld as i32;
        Ok((mloc, nloc))
    }

    /// This rank's part of a distributed Schur complement (column-major,
    /// leading dimension SCHUR_LLD = SCHUR_MLOC), after the factorization.
    pub fn schur_local(&self) -> &[f64] {
        &self.schur
    }

    /// The Schur complement (host), as MUMPS returns it: its lower triangle
    /// by rows, that is its upper triangle column-major (what
    /// [`crate::dense`] reads); the strict lower triangle (column-major) is
    /// not set.
    pub fn schur_upper(&self) -> &[f64] {
        &self.schur
    }

    fn run(&mut self, job: i32, phase: &str) -> Result<(), Error> {
        self.id.job = job;
        // SAFETY: the instance made in `new`; its pointers are null or into
        // arrays of ours of the sizes stated beside them (the module's
        // invariant).
        unsafe { sys::dmumps_c(&mut *self.id) };
        self.check(phase)
    }

    /// Analysis (JOB = 1).
    pub fn analyse(&mut self) -> Result<(), Error> {
        self.run(1, "analysis")
    }

    /// Numerical factorization (JOB = 2). A work space found too small is
    /// enlarged (ICNTL(14) doubled) and the factorization redone, up to 5
    /// times.
    pub fn factorize(&mut self) -> Result<(), Error> {
        // Up to 6 tries: 40% to 1280% of the predicted work space (a
        // distributed Schur complement on 4 ranks of a 739-node block
        // needed 400%: MUMPS' estimate of a small root is poor).
        for _ in 0..6 {
            self.id.job = 2;
            // SAFETY: as in `run`.
            unsafe { sys::dmumps_c(&mut *self.id) };
            let code = self.id.infog[0];
            if matches!(code, -8 | -9 | -14 | -15 | -11 | -12 | -17 | -20) {
                let cur = icntl!(self.id, 14).max(20);
                icntl!(self.id, 14) = 2 * cur;
                continue;
            }
            break;
        }
        let code = self.id.infog[0];
        if code == -10 || code == -6 || code == -40 {
            // A singular operator is a property of the scene: name it.
            return Err(Error::IllPosed(format!(
                "the stiffness matrix is singular (MUMPS INFOG(1) = {code}: {}): a part of the mesh can move without deforming and nothing holds it (a mechanism, such as parts joined at a single node, or a rigid motion); check the mesh's connectivity and the Dirichlet conditions",
                meaning(code, self.id.infog[1])
            )));
        }
        self.check("factorization")
    }

    /// Solve (JOB = 3) with the centralized dense right-hand sides `rhs`
    /// (host; `nrhs` columns of length n, column-major), overwritten by the
    /// solutions; `schur_phase`: ICNTL(26) (0: no Schur complement; 1: the
    /// condensation, which leaves the reduced right-hand sides in
    /// [`Mumps::redrhs`]; 2: the expansion from the Schur solutions written
    /// there).
    pub fn solve(
        &mut self,
        rhs: &mut Vec<f64>,
        nrhs: usize,
        schur_phase: i32,
    ) -> Result<(), Error> {
        let n = self.id.n as usize;
        icntl!(self.id, 20) = 0;
        icntl!(self.id, 21) = 0;
        icntl!(self.id, 26) = schur_phase;
        std::mem::swap(&mut self.rhs, rhs);
        if self.host {
            assert_eq!(self.rhs.len(), n * nrhs);
            self.id.rhs = self.rhs.as_mut_ptr();
            self.id.nrhs = nrhs as i32;
            self.id.lrhs = n as i32;
            if schur_phase != 0 {
                self.point_redrhs(nrhs);
            }
        }
        let r = self.run(3, "solve");
        std::mem::swap(&mut self.rhs, rhs);
        // The right-hand sides are the caller's again: no pointer to them
        // is left behind.
        self.id.rhs = std::ptr::null_mut();
        icntl!(self.id, 26) = 0;
        r
    }

    /// Solve (JOB = 3) with distributed right-hand sides and solutions
    /// (ICNTL(20) = 10, ICNTL(21) = 1): `rhs` holds this rank's rows
    /// `irhs` (1-based global indices, each row on one rank) of `nrhs`
    /// columns (column-major, leading dimension `irhs.len()`); the
    /// solutions' rows that MUMPS keeps on this rank (the pivots it
    /// eliminated here, INFO(23) of them, fixed by the factorization) come
    /// back in `sol` (column-major, leading dimension `isol.len()`) with
    /// their 1-based indices in `isol`. `schur_phase` as in
    /// [`Mumps::solve`]; the condensation (1) writes no solution.
    pub fn solve_distributed(
        &mut self,
        rhs: &mut [f64],
        irhs: &mut [i32],
        nrhs: usize,
        schur_phase: i32,
        sol: &mut Vec<f64>,
        isol: &mut Vec<i32>,
    ) -> Result<(), Error> {
        let nloc = irhs.len();
        assert_eq!(rhs.len(), nloc * nrhs);
        let mine = self.id.info[22].max(0) as usize;
        isol.resize(mine, 0);
        sol.resize(mine.max(1) * nrhs, 0.0);
        icntl!(self.id, 20) = 10;
        icntl!(self.id, 21) = 1;
        icntl!(self.id, 26) = schur_phase;
        self.id.nrhs = nrhs as i32;
        self.id.nloc_rhs = nloc as i32;
        self.id.lrhs_loc = nloc.max(1) as i32;
        self.id.rhs_loc = rhs.as_mut_ptr();
        self.id.irhs_loc = irhs.as_mut_ptr();
        self.id.lsol_loc = mine.max(1) as i32;
        self.id.sol_loc = sol.as_mut_ptr();
        self.id.isol_loc = isol.as_mut_ptr();
        if self.host && schur_phase != 0 {
            self.point_redrhs(nrhs);
        }
        let r = self.run(3, "solve");
        // The arrays are the caller's again: no pointer to them is left
        // behind.
        self.id.rhs_loc = std::ptr::null_mut();
        self.id.irhs_loc = std::ptr::null_mut();
        self.id.sol_loc = std::ptr::null_mut();
        self.id.isol_loc = std::ptr::null_mut();
        icntl!(self.id, 20) = 0;
        icntl!(self.id, 21) = 0;
        icntl!(self.id, 26) = 0;
        r
    }

    /// REDRHS (host, with a Schur complement): `nrhs` columns of the Schur
    /// complement's order, MUMPS pointed at them.
    fn point_redrhs(&mut self, nrhs: usize) {
        let m = self.id.size_schur as usize;
        if self.redrhs.len() != m * nrhs {
            self.redrhs.resize(m * nrhs, 0.0);
        }
        self.id.redrhs = self.redrhs.as_mut_ptr();
        self.id.lredrhs = m as i32;
    }

    /// The reduced right-hand sides / Schur solutions (host), `nrhs`
    /// columns of the Schur complement's order.
    pub fn redrhs_mut(&mut self) -> &mut [f64] {
        &mut self.redrhs
    }
}
