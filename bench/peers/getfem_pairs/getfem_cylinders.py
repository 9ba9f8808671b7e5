#!/usr/bin/python3
"""GetFEM peer for ubr-petsc's -contact_pair: two elastic quarter cylinders
(tests/pairs/cylinders2d.geo) in frictionless contact, on the mesh file that
ubr-petsc reads.

    /usr/bin/python3 getfem_cylinders.py MESH.msh OUT_STEM [--brick integral|nodal]
        [--im K] [--r R] [--max-res TOL]

Writes OUT_STEM.csv (x, y, lambda_n on the slave arc's nodes: the contact
pressure, positive in compression) and OUT_STEM.json (force, peak, timings).

Why the file is split: GetFEM's gmsh importer merges coincident points, and
the two cylinders each have a node at the origin, where they touch; a single
imported mesh glues the bodies there (2113 nodes in the file for hc 0.0125,
2112 in GetFEM). So the Gmsh 2.2 file is split, by its surface physical
groups "upper" and "lower", into one file per body (the same nodes,
triangles and boundary lines, renumbered), each imported by GetFEM's own
importer, which maps the physical tags to its region numbers.

Model (the scene of tests/pairs.rs cylinders_follow_hertz_and_ranks_agree):
P1 displacements, plane strain, E = 2000, nu = 0.3; "base" uy = 0,
"sym_lower" and "sym_upper" ux = 0 (normal Dirichlet conditions with P1
multipliers: pointwise at the nodes on these straight lines), traction
(0, -2.5) on "top"; contact between "slave" (upper arc, u1) and "master"
(lower arc, u2).

Bricks:
  integral: add_integral_contact_between_nonmatching_meshes_brick, option 1
    (non-symmetric Alart-Curnier augmented Lagrangian, Newton). The
    multiplier is the normal contact stress, a standard (not dual) P1 field
    on the slave arc's nodes; the master displacement enters through a
    projected FEM (each quadrature point of the slave edges projected on the
    master arc), integrated with the slave elements' face quadrature (no
    segmentation at the projections of master nodes): a mortar method with
    element-based integration.
  nodal: add_nodal_contact_between_nonmatching_meshes_brick: node-to-segment,
    one multiplier (a nodal force) per slave node; the pressure reported is
    that force over the node's tributary length (half its two edges).
"""
import argparse
import json
import os
import sys
import tempfile
import time

T0 = time.perf_counter()
import numpy as np  # noqa: E402
import getfem as gf  # noqa: E402

gf.util_trace_level(0)

T_IMPORT = time.perf_counter() - T0

E, NU = 2000.0, 0.3
TRACTION = (0.0, -2.5)


def read_msh22(path):
    """Nodes {id: (x, y)}, physical names {tag: name}, elements [(type, phys, [nodes])]."""
    with open(path) as f:
        lines = f.read().split("\n")
    i, nodes, names, elems = 0, {}, {}, []
    while i < len(lines):
        s = lines[i].strip()
        if s == "$MeshFormat":
            assert lines[i + 1].split()[0].startswith("2."), "Gmsh 2.2 ASCII expected"
        elif s == "$PhysicalNames":
            n = int(lines[i + 1])
            for l in lines[i + 2:i + 2 + n]:
                d, tag, name = l.split(maxsplit=2)
                names[int(tag)] = name.strip('"')
            i += n + 1
        elif s == "$Nodes":
            n = int(lines[i + 1])
            for l in lines[i + 2:i + 2 + n]:
                w = l.split()
                nodes[int(w[0])] = (float(w[1]), float(w[2]))
            i += n + 1
        elif s == "$Elements":
            n = int(lines[i + 1])
            for l in lines[i + 2:i + 2 + n]:
                w = [int(v) for v in l.split()]
                typ, ntag = w[1], w[2]
                elems.append((typ, w[3], w[3 + ntag:]))
            i += n + 1
        i += 1
    return nodes, names, elems


def split_bodies(path, outdir):
    """One Gmsh 2.2 file per surface physical group; returns {name: file}."""
    nodes, names, elems = read_msh22(path)
    tag = {v: k for k, v in names.items()}
    files = {}
    for body in ("upper", "lower"):
        tris = [e for e in elems if e[0] == 2 and e[1] == tag[body]]
        used = sorted({n for e in tris for n in e[2]})
        uset = set(used)
        lines_ = [e for e in elems if e[0] == 1 and all(n in uset for n in e[2])]
        # the boundary lines whose nodes are this body's (the bodies share
        # no node: the two at the origin are distinct in the file)
        keep = lines_ + tris
        out = os.path.join(outdir, f"{body}.msh")
        with open(out, "w") as f:
            f.write("$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$PhysicalNames\n")
            f.write(f"{len(names)}\n")
            for t, nm in sorted(names.items()):
                dim = 2 if nm in ("upper", "lower") else 1
                f.write(f'{dim} {t} "{nm}"\n')
            f.write("$EndPhysicalNames\n$Nodes\n")
            f.write(f"{len(used)}\n")
            for n in used:
                f.write(f"{n} {nodes[n][0]:.17g} {nodes[n][1]:.17g} 0\n")
            f.write("$EndNodes\n$Elements\n")
            f.write(f"{len(keep)}\n")
            for k, (typ, phys, ns) in enumerate(keep, 1):
                f.write(f"{k} {typ} 2 {phys} {phys} {' '.join(map(str, ns))}\n")
            f.write("$EndElements\n")
        files[body] = out
    return files, tag


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("mesh")
    ap.add_argument("out")
    ap.add_argument("--brick", default="integral", choices=["integral", "nodal", "sliding"])
    ap.add_argument("--im", type=int, default=4, help="IM_TRIANGLE(K)")
    ap.add_argument("--r", type=float, default=E, help="augmentation parameter")
    ap.add_argument("--release", type=float, default=0.5,
                    help="sliding: the raytracing release distance")
    ap.add_argument("--max-res", type=float, default=1e-10)
    ap.add_argument("--noisy", action="store_true")
    ap.add_argument("--shift", type=float, default=0.02,
                    help="initial guess: the upper body moved down by SHIFT "
                         "(the upper body is held in y by the contact only)")
    a = ap.parse_args()

    t = time.perf_counter()
    with tempfile.TemporaryDirectory(prefix="gf_pairs_") as tmp:
        files, tag = split_bodies(a.mesh, tmp)
        m1 = gf.Mesh("import", "gmsh", files["upper"])  # slave body
        m2 = gf.Mesh("import", "gmsh", files["lower"])  # master body
    t_mesh = time.perf_counter() - t
    SL, MA, TOP, SYMU, SYML, BASE = (tag[k] for k in
                                     ("slave", "master", "top", "sym_upper", "sym_lower", "base"))
    for mm, rgs in ((m1, (SL, TOP, SYMU)), (m2, (MA, SYML, BASE))):
        have = set(int(r) for r in mm.regions())
        assert set(rgs) <= have, (rgs, have)

    t = time.perf_counter()
    mf1 = gf.MeshFem(m1, 2); mf1.set_classical_fem(1)
    mf2 = gf.MeshFem(m2, 2); mf2.set_classical_fem(1)
    ppi = gf.Integ(f"IM_TRIANGLE({a.im})")
    mim1 = gf.MeshIm(m1, ppi)
    mim2 = gf.MeshIm(m2, ppi)

    md = gf.Model("real")
    md.add_fem_variable("u1", mf1)
    md.add_fem_variable("u2", mf2)
    md.add_initialized_data("E", [E])
    md.add_initialized_data("nu", [NU])
    md.add_isotropic_linearized_elasticity_pstrain_brick(mim1, "u1", "E", "nu")
    md.add_isotropic_linearized_elasticity_pstrain_brick(mim2, "u2", "E", "nu")
    md.add_initialized_data("t", list(TRACTION))
    md.add_source_term_brick(mim1, "u1", "t", TOP)
    md.add_normal_Dirichlet_condition_with_multipliers(mim1, "u1", 1, SYMU)
    md.add_normal_Dirichlet_condition_with_multipliers(mim2, "u2", 1, SYML)
    md.add_normal_Dirichlet_condition_with_multipliers(mim2, "u2", 1, BASE)
    md.add_initialized_data("r", [a.r])

    slave_dofs = mf1.basic_dof_on_region(SL)  # both components
    if a.brick == "integral":
        mfp1 = gf.MeshFem(m1, 1); mfp1.set_classical_fem(1)
        # the multiplier lives on the slave arc's nodes
        mfl = gf.MeshFem("partial", mfp1, mfp1.basic_dof_on_region(SL))
        md.add_fem_variable("lambda", mfl)
        md.add_integral_contact_between_nonmatching_meshes_brick(
            mim1, "u1", "u2", "lambda", "r", SL, MA, 1)
    elif a.brick == "sliding":
        mfp1 = gf.MeshFem(m1, 2); mfp1.set_classical_fem(1)
        md.add_filtered_fem_variable("lambda", mfp1, SL)
        md.add_initialized_data("fr", [0.0])
        ind = md.add_integral_large_sliding_contact_brick_raytracing(
            "r", a.release, "fr", "1", 0)
        mimc1 = gf.MeshIm(m1, ppi)
        mimc2 = gf.MeshIm(m2, ppi)
        md.add_slave_contact_boundary_to_large_sliding_contact_brick(
            ind, mimc1, SL, "u1", "lambda")
        md.add_master_contact_boundary_to_large_sliding_contact_brick(
            ind, mimc2, MA, "u2")
    else:
        # the brick makes the multiplier itself (one per slave node)
        md.add_nodal_contact_between_nonmatching_meshes_brick(
            mim1, mim2, "u1", "u2", "lambda", "r", SL, MA)

    u1 = md.variable("u1")
    u1[1::2] = -a.shift
    md.set_variable("u1", u1)
    t_setup = time.perf_counter() - t

    t = time.perf_counter()
    nit, conv = md.solve("max_res", a.max_res, "max_iter", 100,
                         *(["noisy"] if a.noisy else []))
    t_solve = time.perf_counter() - t
    nit, conv = int(nit), bool(conv)

    lam = md.variable("lambda")
    if a.brick == "integral":
        # the partial mesh_fem keeps the kept dofs in increasing order
        pts = mfp1.basic_dof_nodes(mfp1.basic_dof_on_region(SL))
        xs, ys = pts[0], pts[1]
        # GetFEM's contact stress is negative in compression
        p = -lam
        # force on the slave: the integral of the stress vector lambda n
        # (n the slave's outward normal), its y component
        fy = gf.asm_generic(mim1, 0, "-lambda*Normal(2)", SL, md)
        # GetFEM's stress acts along the master's normal; the integral of the
        # multiplier on its own is the resultant's size up to cos
        fabs = gf.asm_generic(mim1, 0, "-lambda", SL, md)
    elif a.brick == "sliding":
        # lambda: the contact stress vector on the slave arc (P1, x/y pairs)
        dl = mfp1.basic_dof_on_region(SL)
        pts = mfp1.basic_dof_nodes(dl[0::2])
        xs, ys = pts[0], pts[1]
        lx, ly = lam[0::2], lam[1::2]
        # the slave's outward normal at the node: the arc of radius 4
        # centred (0, 4)
        nx, ny = xs / 4.0, (ys - 4.0) / 4.0
        nn = np.hypot(nx, ny); nx, ny = nx / nn, ny / nn
        p = -(lx * nx + ly * ny)
        fy = gf.asm_generic(mim1, 0, "lambda(2)", SL, md)
        fabs = gf.asm_generic(mim1, 0, "-lambda.Normal", SL, md)
    else:
        # the nodal brick numbers its multipliers after the slave dofs
        # (x, y pairs of mf1 on the slave region, in order)
        pts = mf1.basic_dof_nodes(slave_dofs[0::2])
        xs, ys = pts[0], pts[1]
        order = np.argsort(xs)
        # tributary length of each slave node along the arc
        xo, yo = xs[order], ys[order]
        seg = np.hypot(np.diff(xo), np.diff(yo))
        w = np.zeros(len(xo)); w[:-1] += seg / 2; w[1:] += seg / 2
        wt = np.empty_like(w); wt[order] = w
        p = -lam / wt
        fabs = float(-lam.sum())
        fy = fabs  # nodal forces along the master normals; near-vertical
    order = np.argsort(xs)
    xs, ys, p = xs[order], ys[order], p[order]

    res = dict(brick=a.brick, option=1 if a.brick == "integral" else None,
               im=a.im, r=a.r, max_res=a.max_res, newton_iterations=nit,
               converged=conv, nodes=int(m1.nbpts() + m2.nbpts()),
               elements=int(m1.nbcvs() + m2.nbcvs()),
               slave_nodes=int(len(xs)),
               contact_force_y=float(fy), contact_force_abs=float(fabs),
               peak_pressure=float(p.max()),
               min_pressure=float(p.min()),
               time_import=T_IMPORT, time_mesh=t_mesh, time_setup=t_setup,
               time_solve=t_solve,
               time_total=time.perf_counter() - T0)
    with open(a.out + ".json", "w") as f:
        json.dump(res, f, indent=1)
    with open(a.out + ".csv", "w") as f:
        f.write("x,y,lambda_n\n")
        for x, y, v in zip(xs, ys, p):
            f.write(f"{x:.17g},{y:.17g},{v:.17g}\n")
    print(json.dumps(res))
    return 0 if conv else 3


if __name__ == "__main__":
    sys.exit(main())
