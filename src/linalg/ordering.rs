//! The orderings of the direct back-end ([`super::direct`]): the choice
//! (`choose`) among METIS on the host, MUMPS' own orderings
//! (`-mat_mumps_icntl_7 K`, with what MUMPS used read back), MUMPS'
//! parallel analysis ([`mumps_parallel`]), and below, a nested-dissection
//! ordering computed by every rank at once, for MUMPS' PERM_IN on several
//! ranks (issue "Scaling studies", item 1).
//!
//! The mesh is already partitioned, one part per rank. The parts are the
//! leaves of a binary tree over the rank range (each range split in two, the
//! left half taking floor(P/2) ranks); an edge between parts a < b crosses
//! between the two subtrees of the tree node where a and b part, and its
//! endpoint on the lower rank's side goes into that node's separator (the
//! highest such node when it has several). Every edge between two subtrees
//! of a node then has an endpoint in its separator or above, so the
//! separators separate: the order "the leaves' interiors, each separator
//! after its two subtrees" (the tree in post-order) is a nested dissection
//! whose top levels follow the partition. Each rank orders its own interior
//! with METIS_NodeND meanwhile — the whole graph's METIS_NodeND on rank 0
//! took 2.5 s of a 7.8 s run on 2 ranks (582k-node 2D scene), with the other
//! rank waiting. Each separator keeps its nodes in rank order: it is
//! eliminated as one front at the top of its subtree.
//!
//! The Schur unknowns (components `comps` of the contact nodes) are
//! ordered last, as [`super::direct`]'s sequential ordering does.

use super::direct::host_verdict;
use crate::comm::{allreduce_max, Layout};
use crate::error::Error;
use crate::fem::Adjacency;
use crate::mesh::distribute::LocalMesh;
use crate::mumps::Mumps;
use crate::petsc::{options, LogEvent};
use mpi::traits::*;

/// The tree node of the rank range where ranks `a` and `b` part: its range
/// `(lo, hi)` and depth.
fn parting(a: usize, b: usize, p: usize) -> (usize, usize, usize) {
    let (mut lo, mut hi, mut depth) = (0, p, 0);
    loop {
        let mid = lo + (hi - lo) / 2;
        if a < mid && b < mid {
            hi = mid;
        } else if a >= mid && b >= mid {
            lo = mid;
        } else {
            return (lo, hi, depth);
        }
        depth += 1;
    }
}

/// The internal tree nodes (ranges of two or more ranks) and the leaves, in
/// post-order: `(lo, hi)`, a leaf being `(r, r + 1)`.
fn post_order(lo: usize, hi: usize, out: &mut Vec<(usize, usize)>) {
    if hi - lo >= 2 {
        let mid = lo + (hi - lo) / 2;
        post_order(lo, mid, out);
        post_order(mid, hi, out);
    }
    out.push((lo, hi));
}

/// METIS_NodeND of a graph in compressed rows (no self loops); the order as
/// a list of vertices (new -> old).
pub(super) fn metis_nd(xadj: &mut [i32], adjncy: &mut [i32]) -> Result<Vec<i32>, Error> {
    let n = xadj.len() - 1;
    let mut perm = vec![0i32; n];
    let mut iperm = vec![0i32; n];
    if n == 0 {
        return Ok(perm);
    }
    let mut nvtxs = n as i32;
    let mut options = [0i32; metis_sys::METIS_NOPTIONS as usize];
    // SAFETY: the arrays are valid for the sizes METIS reads (n + 1 row
    // pointers, xadj[n] neighbours, n entries of perm and iperm), and METIS
    // keeps no pointer after the call.
    let r = unsafe {
        metis_sys::METIS_SetDefaultOptions(options.as_mut_ptr());
        metis_sys::METIS_NodeND(
            &mut nvtxs,
            xadj.as_mut_ptr(),
            adjncy.as_mut_ptr(),
            std::ptr::null_mut(),
            options.as_mut_ptr(),
            perm.as_mut_ptr(),
            iperm.as_mut_ptr(),
        )
    };
    if r == metis_sys::rstatus_et_METIS_ERROR_MEMORY {
        return Err(Error::OutOfMemory(format!(
            "METIS could not allocate the nested-dissection ordering of {n} nodes"
        )));
    }
    if r != metis_sys::rstatus_et_METIS_OK {
        return Err(Error::Internal(format!("METIS_NodeND failed ({r})")));
    }
    Ok(perm)
}

/// PERM_IN on the host (empty elsewhere): the parallel nested dissection
/// of the nodal graph (see the module documentation), each node's `d` dofs
/// in a row, except the Schur unknowns (components `comps` of the nodes
/// `schur_nodes`, in that order), last. Collective.
pub fn parallel_nd<C: Communicator>(
    world: &C,
    mesh: &LocalMesh,
    (ptr, nbr): &Adjacency,
    schur_nodes: &[usize],
    comps: &[usize],
) -> Result<Vec<i32>, Error> {
    let p = world.size() as usize;
    let me = world.rank() as usize;
    let nown = mesh.owned_count;
    // The first global node of every rank (owned nodes are contiguous).
    let starts: Vec<u64> = Layout::new(world, 1).all_gather(world, &[mesh.owned_start as u64]);
    let rank_of = |g: usize| -> usize { starts.partition_point(|&s| s as usize <= g) - 1 };
    // Each owned node's separator: the highest tree node where an edge to a
    // higher rank crosses (None: interior).
    let mut sep: Vec<Option<(usize, usize, usize)>> = vec![None; nown];
    for a in 0..nown {
        for &b in &nbr[ptr[a]..ptr[a + 1]] {
            let b = b as usize;
            if b < nown {
                continue;
            }
            let r = rank_of(mesh.node_global[b]);
            if r <= me {
                continue;
            }
            let t = parting(me, r, p);
            if sep[a].is_none_or(|s| t.2 < s.2) {
                sep[a] = Some(t);
            }
        }
    }
    let (interior, order) = order_interior(&sep, ptr, nbr);
    // METIS failing on one rank is made collective.
    let failed = order.is_err();
    let any = allreduce_max(world, if failed { 1.0 } else { 0.0 });
    let order = match (order, any > 0.0) {
        (Ok(o), false) => o,
        (Err(e), _) => return Err(e),
        (Ok(_), true) => {
            return Err(Error::Internal(
                "METIS failed on another rank's part".into(),
            ))
        }
    };
    // The segments in post-order and their sizes: a leaf's interior, or a
    // separator (its nodes rank by rank).
    let mut segments = Vec::new();
    post_order(0, p, &mut segments);
    let nseg = segments.len();
    let seg_of = |t: (usize, usize)| segments.iter().position(|&s| s == t).expect("a tree node");
    let mut mine = vec![0.0f64; nseg];
    mine[seg_of((me, me + 1))] = interior.len() as f64;
    for s in sep.iter().flatten() {
        mine[seg_of((s.0, s.1))] += 1.0;
    }
    // Every rank's count of every segment.
    let counts = Layout::new(world, nseg).all_gather(world, &mine);
    let count = |r: usize, s: usize| counts[r * nseg + s] as usize;
    let seg_start: Vec<usize> = (0..nseg)
        .scan(0usize, |total, s| {
            let start = *total;
            *total += (0..p).map(|r| count(r, s)).sum::<usize>();
            Some(start)
        })
        .collect();
    // This rank's offset inside each segment (the ranks before it).
    let mut offset: Vec<usize> = (0..nseg)
        .map(|s| seg_start[s] + (0..me).map(|r| count(r, s)).sum::<usize>())
        .collect();
    // Each owned node's position.
    let mut pos = vec![0usize; nown];
    let leaf = seg_of((me, me + 1));
    for &i in &order {
        pos[interior[i as usize]] = offset[leaf];
        offset[leaf] += 1;
    }
    for (a, s) in sep.iter().enumerate() {
        if let Some(s) = s {
            let k = seg_of((s.0, s.1));
            pos[a] = offset[k];
            offset[k] += 1;
        }
    }
    gather_order(world, mesh, &pos, schur_nodes, comps)
}

/// METIS_NodeND of the interior nodes (those in no separator) of this
/// rank's part: the interior (local node numbers) and its order (positions
/// in the interior list), or METIS' error (which the caller makes
/// collective).
fn order_interior(
    sep: &[Option<(usize, usize, usize)>],
    ptr: &[usize],
    nbr: &[u32],
) -> (Vec<usize>, Result<Vec<i32>, Error>) {
    let nown = sep.len();
    let mut local = vec![u32::MAX; nown];
    let mut interior = Vec::new();
    for a in 0..nown {
        if sep[a].is_none() {
            local[a] = interior.len() as u32;
            interior.push(a);
        }
    }
    let mut xadj = vec![0i32; interior.len() + 1];
    let mut adjncy = Vec::new();
    for (i, &a) in interior.iter().enumerate() {
        for &b in &nbr[ptr[a]..ptr[a + 1]] {
            let b = b as usize;
            if b != a && b < nown && local[b] != u32::MAX {
                adjncy.push(local[b] as i32);
            }
        }
        xadj[i + 1] = adjncy.len() as i32;
    }
    let order = metis_nd(&mut xadj, &mut adjncy);
    (interior, order)
}

/// The position of every owned node gathered on the host, which turns
/// the node order into MUMPS' PERM_IN (empty on the other ranks).
fn gather_order<C: Communicator>(
    world: &C,
    mesh: &LocalMesh,
    pos: &[usize],
    schur_nodes: &[usize],
    comps: &[usize],
) -> Result<Vec<i32>, Error> {
    let (nown, d) = (mesh.owned_count, mesh.dim);
    // (global node, position) of the owned nodes.
    let mut pairs = Vec::with_capacity(2 * nown);
    for (a, &at) in pos.iter().enumerate() {
        pairs.push(mesh.node_global[a] as f64);
        pairs.push(at as f64);
    }
    let all = Layout::new(world, pairs.len()).gather(world, &pairs);
    if world.rank() != 0 {
        return Ok(Vec::new());
    }
    let n = mesh.global_nodes;
    let mut by_position = vec![usize::MAX; n];
    for pair in all.chunks(2) {
        by_position[pair[1] as usize] = pair[0] as usize;
    }
    if by_position.contains(&usize::MAX) {
        return Err(Error::Internal(
            "the parallel ordering left a position empty".into(),
        ));
    }
    Ok(dof_permutation(&by_position, n, d, schur_nodes, comps))
}

/// PERM_IN (1-based, per dof) from a node order (new -> old): each node's
/// dofs in a row, the Schur unknowns (components `comps` of `schur_nodes`,
/// in that order) last.
pub fn dof_permutation(
    order: &[usize],
    n: usize,
    d: usize,
    schur_nodes: &[usize],
    comps: &[usize],
) -> Vec<i32> {
    let mut in_schur = vec![false; n * d];
    for &g in schur_nodes {
        for &c in comps {
            in_schur[g * d + c] = true;
        }
    }
    let mut perm_in = vec![0i32; n * d];
    let mut next = 0i32;
    for &g in order {
        for c in 0..d {
            if !in_schur[g * d + c] {
                next += 1;
                perm_in[g * d + c] = next;
            }
        }
    }
    for &g in schur_nodes {
        for &c in comps {
            next += 1;
            perm_in[g * d + c] = next;
        }
    }
    perm_in
}

/// PERM_IN on the host (empty elsewhere): METIS nested dissection of the
/// nodal graph, each node's `d` dofs in a row, except the Schur unknowns
/// (components `comps` of the nodes `schur_nodes`, in that order), last.
fn metis_order<C: Communicator>(
    world: &C,
    mesh: &LocalMesh,
    (ptr, nbr): &Adjacency,
    schur_nodes: &[usize],
    comps: &[usize],
) -> Result<Vec<i32>, Error> {
    let d = mesh.dim;
    // Each owned node's neighbours (global numbers), gathered on the host.
    let mut flat: Vec<f64> = Vec::with_capacity(nbr.len() + mesh.owned_count); // node, count, neighbours... (exact in f64)
    for a in 0..mesh.owned_count {
        let row = &nbr[ptr[a]..ptr[a + 1]];
        flat.push(mesh.node_global[a] as f64);
        flat.push((row.len() - 1) as f64); // itself excluded
        flat.extend(
            row.iter()
                .filter(|&&b| b as usize != a)
                .map(|&b| mesh.node_global[b as usize] as f64),
        );
    }
    let layout = Layout::new(world, flat.len());
    let all = layout.gather(world, &flat);
    drop(flat);
    let order = if world.rank() == 0 {
        host_order(&all, mesh.global_nodes, d, schur_nodes, comps)
    } else {
        Ok(Vec::new())
    };
    // METIS runs on the host alone: its failure is made collective.
    let (verdict, order) = match order {
        Ok(order) => (None, order),
        Err(e) => (Some(e), Vec::new()),
    };
    host_verdict(world, verdict)?;
    Ok(order)
}

/// [`metis_order`] on the host, from the gathered lists `all` (node,
/// count, neighbours...).
fn host_order(
    all: &[f64],
    n: usize,
    d: usize,
    schur_nodes: &[usize],
    comps: &[usize],
) -> Result<Vec<i32>, Error> {
    let mut xadj: Vec<i32> = vec![0; n + 1];
    let mut lists: Vec<Vec<i32>> = vec![Vec::new(); n];
    let mut p = 0;
    while p < all.len() {
        let (g, k) = (all[p] as usize, all[p + 1] as usize);
        lists[g] = all[p + 2..p + 2 + k].iter().map(|&x| x as i32).collect();
        p += 2 + k;
    }
    let mut adjncy: Vec<i32> = Vec::new();
    for (g, l) in lists.iter().enumerate() {
        adjncy.extend_from_slice(l);
        xadj[g + 1] = adjncy.len() as i32;
    }
    drop(lists);
    let perm = metis_nd(&mut xadj, &mut adjncy)?;
    let order: Vec<usize> = perm.iter().map(|&g| g as usize).collect();
    Ok(dof_permutation(&order, n, d, schur_nodes, comps))
}

/// In 2D, METIS' nested dissection pays for its own time (it is sequential,
/// about 3-7 us per node here) only when MUMPS' approximate minimum degree
/// ordering predicts more than this many factorization flops per node.
/// Measured (one rank; METIS saves 35-60% of the flops in 2D): Hertz meshes
/// of 6,001 to 259,066 nodes predict 1.7e4 to 2.1e5 and are faster with AMD
/// (hertz_37473: factorization phase 0.32 s against 0.41 s), at 909,078
/// nodes (4.5e5) the two tie; a crowned Coulomb block of 114,646 nodes
/// (2.6e5) is faster with METIS (1.87 s against 2.18 s). In 3D, METIS always
/// (block3d_17887: 5.4e10 flops against 1.4e11 with AMD).
pub const METIS_PAYS_2D: f64 = 2.5e5;

/// With an ordering of ours (PERM_IN), MUMPS' symbolic factorization by
/// column counts (ICNTL(58) = 2) unless `-mat_mumps_icntl_58` chooses: the
/// analysis, sequential on the host, took 0.89 s instead of 1.26 s on 16
/// ranks for the 582k-node 2D scene (2.8% more flops, the same numerical
/// factorization time), and the 3D scene's flops were unchanged
/// (bench/results/device16/2026-11-26-c-local.log).
fn column_counts(mumps: &mut Mumps) -> Result<(), Error> {
    if options::get_string("-mat_mumps_icntl_58")?.is_none() {
        mumps.set_icntl(58, 2);
    }
    Ok(())
}

/// Analyses with the ordering the options ask for (`-mat_mumps_icntl_7 K`:
/// 1 is METIS, others MUMPS' own K), else the one predicted faster: METIS
/// in 3D; in 2D, MUMPS' AMD unless its predicted flops per node exceed
/// [`METIS_PAYS_2D`] (then METIS, and the analysis again). Returns the
/// ordering's description for the summary.
pub(super) fn choose<C: Communicator>(
    world: &C,
    mumps: &mut Mumps,
    mesh: &LocalMesh,
    adjacency: &Adjacency,
    schur_nodes: &[usize],
    comps: &[usize],
) -> Result<String, Error> {
    let ev_analysis = LogEvent::register("MUMPSAnalysis")?;
    let metis = |mumps: &mut Mumps| -> Result<(), Error> {
        let perm_in = {
            let _e = LogEvent::register("METISOrdering")?.begin();
            metis_order(world, mesh, adjacency, schur_nodes, comps)?
        };
        mumps.set_ordering(perm_in);
        column_counts(mumps)?;
        let _e = ev_analysis.begin();
        mumps.analyse()
    };
    let user = options::get_string("-mat_mumps_icntl_7")?.map(|v| v.trim().to_string());
    match user.as_deref() {
        Some("1") => {
            metis(mumps)?;
            return Ok("METIS nested dissection (-mat_mumps_icntl_7 1)".into());
        }
        Some(k) => {
            let k: i32 = k.parse().map_err(|_| {
                Error::BadInput(format!(
                    "option -mat_mumps_icntl_7: '{k}' is not an integer"
                ))
            })?;
            mumps.set_icntl(7, k);
            let _e = ev_analysis.begin();
            mumps.analyse()?;
            let used = mumps.infog(7);
            return Ok(if k == 7 {
                format!(
                    "MUMPS' automatic choice (-mat_mumps_icntl_7 7): {}",
                    mumps_ordering(used)
                )
            } else if used == k {
                format!("MUMPS' {} (-mat_mumps_icntl_7 {k})", mumps_ordering(k))
            } else {
                format!(
                    "MUMPS' {} in place of {} (-mat_mumps_icntl_7 {k}; INFOG(7) = {used})",
                    mumps_ordering(used),
                    mumps_ordering(k)
                )
            });
        }
        None => {}
    }
    if world.size() > 1 {
        // Several ranks: every rank orders its part at once (2D too: the
        // sequential METIS' time is what made AMD the better choice there).
        let perm_in = {
            let _e = LogEvent::register("ParallelOrdering")?.begin();
            parallel_nd(world, mesh, adjacency, schur_nodes, comps)?
        };
        mumps.set_ordering(perm_in);
        column_counts(mumps)?;
        let _e = ev_analysis.begin();
        mumps.analyse()?;
        return Ok(format!(
            "nested dissection in parallel: METIS on each rank's part, the separators from the partition, over {} ranks",
            world.size()
        ));
    }
    if mesh.dim == 3 {
        metis(mumps)?;
        return Ok("METIS nested dissection".into());
    }
    mumps.set_icntl(7, 0);
    {
        let _e = ev_analysis.begin();
        mumps.analyse()?;
    }
    let per_node = mumps.rinfog(1) / mesh.global_nodes.max(1) as f64;
    if per_node <= METIS_PAYS_2D {
        return Ok(format!(
            "MUMPS' AMD: {per_node:.1e} flops per node, METIS pays above {METIS_PAYS_2D:.1e}"
        ));
    }
    metis(mumps)?;
    Ok(format!(
        "METIS nested dissection: AMD predicted {per_node:.1e} flops per node, above {METIS_PAYS_2D:.1e}"
    ))
}

/// MUMPS' name of its ordering `k` (ICNTL(7), INFOG(7)).
pub(crate) fn mumps_ordering(k: i32) -> &'static str {
    match k {
        0 => "AMD",
        1 => "given ordering",
        2 => "AMF",
        3 => "SCOTCH",
        4 => "PORD",
        5 => "METIS",
        6 => "QAMD",
        _ => "automatic choice",
    }
}

/// The warning of an ordering `-mat_mumps_icntl_7 K` asked for that MUMPS
/// replaced by another (read after the analysis in INFOG(7)), in silence:
/// Debian's MUMPS has neither METIS (5) nor SCOTCH (3), and with a Schur
/// complement it uses AMD. None for K = 1 (the program's METIS), 7
/// (MUMPS' own choice), MUMPS' parallel analysis, no K, or no analysis
/// (`analysed` false).
pub(super) fn replaced_ordering(mumps: &Mumps, analysed: bool) -> Result<Option<String>, Error> {
    if !analysed {
        return Ok(None);
    }
    let asked = options::get_string("-mat_mumps_icntl_7")?.and_then(|v| v.trim().parse().ok());
    let used = mumps.infog(7);
    let Some(k) = asked.filter(|&k| k != 1 && k != 7 && k != used && mumps.icntl(28) != 2) else {
        return Ok(None);
    };
    let (asked_name, used_name) = (mumps_ordering(k), mumps_ordering(used));
    let why = if mumps.icntl(19) != 0 {
        // Measured with Debian's MUMPS 5.5: with the Schur block every
        // ordering but the given one (METIS) became AMD.
        "MUMPS orders with AMD when it makes the Schur complement of the condensed contact unknowns; -mat_mumps_icntl_7 1 orders them with METIS, -ubr_condense_max 0 condenses nothing"
            .to_string()
    } else {
        format!("this MUMPS was built without {asked_name}")
    };
    Ok(Some(format!(
        "-mat_mumps_icntl_7 {k} asks for MUMPS' {asked_name} ordering, but MUMPS ordered with {used_name} (INFOG(7) = {used}): {why}"
    )))
}

/// MUMPS' own parallel analysis (`-mat_mumps_icntl_28 2`) instead of the
/// program's ordering, which MUMPS analyses sequentially only. Refused with
/// the Schur complement, which MUMPS refuses with it (INFOG(1) = -39).
/// Without `-mat_mumps_icntl_29` (or with 0) PT-Scotch and then ParMETIS
/// are tried: MUMPS' own choice (ICNTL(29) = 0), in a MUMPS with neither
/// (Debian's plain build), writes to its error stream, which the program
/// closes, and the process dies in the Fortran runtime. Collective;
/// returns the ordering's description.
pub fn mumps_parallel(mumps: &mut Mumps, condensed: bool) -> Result<String, Error> {
    if condensed {
        return Err(Error::BadInput(
            "option -mat_mumps_icntl_28 2: MUMPS' parallel analysis cannot be used with the Schur complement on the contact unknowns (MUMPS stops with INFOG(1) = -39); add -ubr_condense_max 0 (a full sparse solve per UBR iteration), or leave ICNTL(28) to the program".into(),
        ));
    }
    let given = options::get_string("-mat_mumps_icntl_29")?.is_some() && mumps.icntl(29) != 0;
    let tools = if given {
        vec![mumps.icntl(29)]
    } else {
        vec![1, 2]
    };
    let name = |t: i32| match t {
        1 => "PT-Scotch",
        2 => "ParMETIS",
        _ => "MUMPS' choice",
    };
    let _e = LogEvent::register("MUMPSAnalysis")?.begin();
    for &t in &tools {
        mumps.set_icntl(29, t);
        match mumps.analyse() {
            Ok(()) => {
                return Ok(format!(
                    "MUMPS' parallel analysis (-mat_mumps_icntl_28 2), ordered by {}",
                    name(t)
                ))
            }
            Err(_) if mumps.infog(1) == -38 => continue,
            Err(e) => return Err(e),
        }
    }
    let tried: Vec<&str> = tools.iter().map(|&t| name(t)).collect();
    Err(Error::BadInput(format!(
        "option -mat_mumps_icntl_28 2: this MUMPS was built without {} (MUMPS stops with INFOG(1) = -38); Debian's libmumps-ptscotch has PT-Scotch (README), or leave ICNTL(28) to the program",
        tried.join(" and ")
    )))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ranks_part_at_their_lowest_common_range() {
        assert_eq!(parting(0, 1, 2), (0, 2, 0));
        // 5 ranks: [0, 2) and [2, 5); then [2, 3) and [3, 5).
        assert_eq!(parting(0, 1, 5), (0, 2, 1));
        assert_eq!(parting(1, 4, 5), (0, 5, 0));
        assert_eq!(parting(2, 4, 5), (2, 5, 1));
        assert_eq!(parting(3, 4, 5), (3, 5, 2));
        let mut order = Vec::new();
        post_order(0, 4, &mut order);
        assert_eq!(
            order,
            vec![(0, 1), (1, 2), (0, 2), (2, 3), (3, 4), (2, 4), (0, 4)]
        );
    }

    #[test]
    fn schur_unknowns_go_last() {
        // Three 2D nodes in the order 2, 0, 1; node 1's y in the Schur block.
        let perm = dof_permutation(&[2, 0, 1], 3, 2, &[1], &[1]);
        assert_eq!(perm, vec![3, 4, 5, 6, 1, 2]);
    }
}
