//! Whether a run fits in the memory of each machine, checked before the
//! assembly and before the factorization. Linux grants allocations it
//! cannot back (overcommit), so a run larger than the machine is not
//! refused by its allocations: the kernel kills a rank (signal 9, mpirun's
//! notice, nothing written). Measured on this 24 GB machine, 2 ranks, the
//! generated block with the default direct solver: at `-mesh_h 0.006`
//! (28M unknowns) killed during the assembly; at `-mesh_h 0.01` (6.2M) the
//! factorization would need 303 GB. Now the need of each rank, summed over
//! the ranks of each machine, is compared with what that machine has free
//! (MemAvailable and SwapFree, within the memory cgroup's limit where one
//! is set; or `-ubr_memory_mb`): before the assembly a lower bound, the
//! stiffness matrix alone ([`assembly_fits`]); after MUMPS' analysis its
//! prediction, INFO(15) ([`fits`]). A run that cannot fit ends with the
//! numbers and exit status 4.

use crate::comm::{allreduce_max_n, allreduce_sum};
use crate::error::Error;
use crate::mumps::Mumps;
use crate::options::declared::{UBR_MEMORY_MB, UBR_MEMORY_RESERVE};
use crate::petsc::options;
use mpi::topology::Communicator;

/// The memory cgroup's files, v2 then v1: its limit, its usage, its
/// statistics and their key for the inactive file pages.
const CGROUPS: [(&str, &str, &str, &str); 2] = [
    (
        "/sys/fs/cgroup/memory.max",
        "/sys/fs/cgroup/memory.current",
        "/sys/fs/cgroup/memory.stat",
        "inactive_file",
    ),
    (
        "/sys/fs/cgroup/memory/memory.limit_in_bytes",
        "/sys/fs/cgroup/memory/memory.usage_in_bytes",
        "/sys/fs/cgroup/memory/memory.stat",
        "total_inactive_file",
    ),
];

/// MB free on this machine for new allocations: MemAvailable + SwapFree
/// (`/proc/meminfo`), at most the room left under the memory cgroup's
/// limit (v2 `memory.max`, v1 `memory.limit_in_bytes`), the group's
/// inactive file pages counted as room (its usage counts the page cache,
/// which the kernel reclaims before it kills: a container that has read
/// large files would otherwise look full). `None` where `/proc/meminfo`
/// cannot be read.
pub fn available_mb() -> Option<f64> {
    let meminfo = std::fs::read_to_string("/proc/meminfo").ok()?;
    let free =
        meminfo_kb(&meminfo, "MemAvailable")? + meminfo_kb(&meminfo, "SwapFree").unwrap_or(0.0);
    let mut mb = free / 1024.0;
    for &(limit, usage, stat, cache) in &CGROUPS {
        if let (Some(l), Some(u)) = (read_bytes(limit), read_bytes(usage)) {
            // An unlimited v1 group reads as about 2^63.
            if l < 1e18 {
                let cached = std::fs::read_to_string(stat)
                    .ok()
                    .and_then(|t| stat_bytes(&t, cache))
                    .unwrap_or(0.0)
                    .min(u);
                mb = mb.min((l - u + cached).max(0.0) / (1024.0 * 1024.0));
            }
        }
    }
    Some(mb)
}

/// The value of `key` in a cgroup's `memory.stat` text ("key bytes" lines).
fn stat_bytes(text: &str, key: &str) -> Option<f64> {
    text.lines().find_map(|l| {
        let (k, v) = l.split_once(' ')?;
        (k == key).then(|| v.trim().parse().ok()).flatten()
    })
}

/// MB of this machine: MemTotal + SwapTotal, at most its memory cgroup's
/// limit.
fn total_mb() -> Option<f64> {
    let meminfo = std::fs::read_to_string("/proc/meminfo").ok()?;
    let total =
        meminfo_kb(&meminfo, "MemTotal")? + meminfo_kb(&meminfo, "SwapTotal").unwrap_or(0.0);
    let mut mb = total / 1024.0;
    for &(limit, ..) in &CGROUPS {
        if let Some(l) = read_bytes(limit).filter(|&l| l < 1e18) {
            mb = mb.min(l / (1024.0 * 1024.0));
        }
    }
    Some(mb)
}

/// The reserve a run keeps free on its machine when `-ubr_memory_reserve`
/// is not given: 3% of the machine's memory, between 256 MB and 2 GB
/// (720 MB on this project's 24 GB machines). At 2 ranks a large assembly
/// takes about 0.5 GB a second per rank, and the watch looks every
/// [`WATCH_MS`] ms.
fn default_reserve_mb() -> Option<f64> {
    Some((0.03 * total_mb()?).clamp(256.0, 2048.0))
}

/// Milliseconds between two looks of the watch at the free memory.
const WATCH_MS: u64 = 50;

/// This process's resident memory in MB (VmRSS; 0 if unknown).
fn resident_mb() -> f64 {
    std::fs::read_to_string("/proc/self/status")
        .ok()
        .and_then(|s| meminfo_kb(&s, "VmRSS"))
        .map_or(0.0, |kb| kb / 1024.0)
}

/// Watches the free memory of this rank's machine while the run works: a
/// run that leaves less than the reserve (`-ubr_memory_reserve MB`, by
/// default [`default_reserve_mb`]; 0: no watch) ends with one line naming
/// the phase and exit status 4 on every rank, before the system's
/// out-of-memory killer ends a rank with signal 9 and nothing said. The
/// checks before the assembly and the factorization ([`assembly_fits`],
/// [`fits`]) refuse what is sure not to fit; between them the need is not
/// predicted: the generated block at `-mesh_h 0.0072` (16.4M unknowns) on 2
/// ranks of this 24 GB machine passed the first, filled the machine in
/// MUMPS' analysis and was killed after 110 s (12.2 GB on a rank). A CG +
/// GAMG run peaks at about six times its matrix (70 bytes per entry: 22.5
/// GB for the 2.4M-node block on 2 ranks). A machine already below the
/// reserve at the start is refused at once (`Err`, on every rank).
pub fn watch<C: Communicator>(world: &C) -> Result<(), Error> {
    // Every collective first: what each rank then decides is its own (a
    // machine whose memory cannot be read is not watched).
    // One line per machine: its first rank's (the others end a moment
    // later, if MPI_Abort has not ended them).
    let leader = world.split_shared(world.rank()).rank() == 0;
    let given = UBR_MEMORY_RESERVE.real()?;
    let reserve = given.or_else(default_reserve_mb).filter(|&r| r > 0.0);
    let how = if given.is_some() {
        "-ubr_memory_reserve"
    } else {
        "3% of its memory; -ubr_memory_reserve MB sets it, 0 turns this watch off"
    };
    let avail = available_mb();
    let low = match (reserve, avail) {
        (Some(r), Some(a)) if a < r => [-a, r],
        _ => [f64::NEG_INFINITY, 0.0],
    };
    let [least, its_reserve] = allreduce_max_n(world, low);
    if least > f64::NEG_INFINITY {
        return Err(Error::OutOfMemory(format!(
            "a machine of the run has {:.0} MB free (free memory and swap), less than the {its_reserve:.0} MB a run keeps free ({how})",
            -least
        )));
    }
    let (Some(reserve), Some(_)) = (reserve, avail) else {
        return Ok(());
    };
    let rank = world.rank();
    // A thread that cannot start (a memory limit with no room for its
    // stack) leaves the run unwatched.
    let _ = std::thread::Builder::new()
        .name("memory watch".into())
        .stack_size(256 << 10)
        .spawn(move || loop {
            std::thread::sleep(std::time::Duration::from_millis(WATCH_MS));
            let Some(a) = available_mb().filter(|&a| a < reserve) else {
                continue;
            };
            if !leader {
                std::thread::sleep(std::time::Duration::from_secs(2));
            }
            let phase = crate::progress::current().unwrap_or_else(|| "starting".into());
            let line = format!(
                "error: out of memory: the free memory of this machine fell to {a:.0} MB, below the {reserve:.0} MB a run keeps free ({how}), while {phase}, rank {rank} holding {:.0} MB; use more machines or a coarser mesh\n",
                resident_mb()
            );
            crate::error::memory::end_out_of_memory(&line);
        });
    Ok(())
}

/// The value in kB of `key` in the text of `/proc/meminfo`.
fn meminfo_kb(text: &str, key: &str) -> Option<f64> {
    text.lines()
        .find_map(|l| l.strip_prefix(key)?.strip_prefix(':'))
        .and_then(|rest| rest.split_whitespace().next()?.parse().ok())
}

/// A number of bytes in a cgroup file (`None` for "max" or no file).
fn read_bytes(path: &str) -> Option<f64> {
    std::fs::read_to_string(path).ok()?.trim().parse().ok()
}

/// The machine with the largest need over free memory, when some need
/// exceeds it: its need in MB summed over its ranks, its largest rank's,
/// its free memory (or `-ubr_memory_mb`) and its ranks; and whether the
/// budget was the user's. `None` (on every rank) when all fit or the free
/// memory cannot be read.
fn over_budget<C: Communicator>(world: &C, need: f64) -> Result<Option<([f64; 4], bool)>, Error> {
    let node = world.split_shared(world.rank());
    let [node_need, node_ranks] = allreduce_sum(&node, [need, 1.0]);
    let [node_largest] = allreduce_max_n(&node, [need]);
    let given = UBR_MEMORY_MB.real()?;
    let avail = given.or_else(available_mb);
    // The ratio need / free of this machine (0 where unknown).
    let ratio = avail.map_or(0.0, |a| node_need / a.max(1.0));
    let [worst] = allreduce_max_n(world, [ratio]);
    if worst <= 1.0 {
        return Ok(None);
    }
    let mine = if ratio == worst {
        [node_need, node_largest, avail.unwrap_or(0.0), node_ranks]
    } else {
        [0.0; 4]
    };
    Ok(Some((allreduce_max_n(world, mine), given.is_some())))
}

/// The words of an over-budget machine: "N MB on the P ranks of one
/// machine (L MB on the largest), ..." and why that is too much.
fn over_words([need, largest, avail, ranks]: [f64; 4], given: bool) -> String {
    let plural = if ranks == 1.0 { "" } else { "s" };
    let room = if given {
        format!("more than the {avail:.0} MB that -ubr_memory_mb allows them")
    } else {
        format!("and {avail:.0} MB are free there (free memory and swap): the system would kill the run")
    };
    format!("{need:.0} MB on the {ranks} rank{plural} of one machine ({largest:.0} MB on the largest), {room}")
}

/// After the analysis: `Err(OutOfMemory)` on every rank when on some
/// machine the factorization's predicted memory, summed over its ranks,
/// exceeds what the machine has free (or `-ubr_memory_mb`, what its ranks
/// may use together). Skipped when the user caps MUMPS'
/// memory (`-mat_mumps_icntl_23`: MUMPS then refuses itself) or where the
/// free memory cannot be read.
pub fn fits<C: Communicator>(world: &C, mumps: &Mumps) -> Result<(), Error> {
    if options::get_string("-mat_mumps_icntl_23")?.is_some() {
        return Ok(());
    }
    // INFO(15), MB, in millions of MB when negative.
    let need = match mumps.info(15) {
        v if v < 0 => -(v as f64) * 1e6,
        v => v as f64,
    };
    let Some((numbers, given)) = over_budget(world, need)? else {
        return Ok(());
    };
    Err(Error::OutOfMemory(format!(
        "MUMPS' analysis predicts that the factorization needs {}; use more machines, the iterative solver (-ksp_type cg -pc_type gamg, a fraction of the memory), or a coarser mesh (-mat_mumps_icntl_23 MB caps each rank's memory and skips this check)",
        over_words(numbers, given)
    )))
}

/// Bytes per stored entry of the stiffness matrix that a run surely
/// allocates: its column index and value (4 + 8), and with MUMPS called
/// directly the lower triangle's triplet (4 + 4 + 8 for half the entries).
const BYTES_PER_ENTRY: [f64; 2] = [12.0, 20.0];

/// Before the assembly: `Err(OutOfMemory)` on every rank when on some
/// machine the stiffness matrix alone (`entries` on this rank; with MUMPS
/// called directly, `direct`, its triplets too) exceeds the free memory
/// (or `-ubr_memory_mb`). A lower bound of the run's memory, so it refuses
/// nothing that could run: the generated block at -mesh_h 0.006 (28M
/// unknowns, 1.3e9 entries: 25.6 GB) on 2 ranks of this 24 GB machine,
/// killed by the system during the assembly before.
pub fn assembly_fits<C: Communicator>(
    world: &C,
    entries: usize,
    direct: bool,
) -> Result<(), Error> {
    let bytes = entries as f64 * BYTES_PER_ENTRY[usize::from(direct)];
    let Some((numbers, given)) = over_budget(world, bytes / (1u64 << 20) as f64)? else {
        return Ok(());
    };
    let what = if direct {
        "the stiffness matrix alone (its entries, and MUMPS' copy of its lower triangle; the factorization needs many times more)"
    } else {
        "the stiffness matrix alone"
    };
    Err(Error::OutOfMemory(format!(
        "{what} needs {}; use more machines or a coarser mesh",
        over_words(numbers, given)
    )))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn meminfo_fields() {
        let text = "MemTotal:       24683656 kB\nMemFree:  100 kB\nMemAvailable:   24067480 kB\nSwapFree:              0 kB\n";
        assert_eq!(meminfo_kb(text, "MemAvailable"), Some(24067480.0));
        assert_eq!(meminfo_kb(text, "SwapFree"), Some(0.0));
        assert_eq!(meminfo_kb(text, "Mem"), None);
        assert_eq!(meminfo_kb(text, "Cached"), None);
        let stat = "anon 100\nfile 5000\nactive_file 1000\ninactive_file 4000\n";
        assert_eq!(stat_bytes(stat, "inactive_file"), Some(4000.0));
        assert_eq!(stat_bytes(stat, "file"), Some(5000.0));
        assert_eq!(stat_bytes(stat, "total_inactive_file"), None);
        let mb = available_mb().expect("/proc/meminfo on Linux");
        assert!(mb > 0.0, "{mb}");
    }
}
