//! How far a solution is from the small deformations the model assumes:
//! the strain of a cell and whether its deformed shape `x + u` is inverted.
//! With `J` the cell's edge matrix (columns `x_a - x_0`) and `J'` the
//! deformed one, `grad u = (J' - J) J^-1` and the cell inverts where
//! `det J'` and `det J` differ in sign.

use super::element;
use nalgebra::{SMatrix, SymmetricEigen};

/// The largest eigenvalue (absolute value) of the symmetric `strain`, or 0
/// when its Frobenius norm (a bound of it) is not above `floor`: the caller
/// wants the maximum over cells, and most cells are below the largest.
macro_rules! largest {
    ($strain:expr, $floor:expr) => {{
        let strain = $strain;
        if strain.norm() <= $floor {
            0.0
        } else {
            SymmetricEigen::new(strain)
                .eigenvalues
                .iter()
                .fold(0.0f64, |a: f64, e| a.max(e.abs()))
        }
    }};
}

macro_rules! deformation {
    ($d:literal, $x:expr, $u:expr, $floor:expr) => {{
        let (x, u) = ($x, $u);
        let j = SMatrix::<f64, $d, $d>::from_fn(|r, c| x[(c + 1) * $d + r] - x[r]);
        let jd = SMatrix::<f64, $d, $d>::from_fn(|r, c| {
            x[(c + 1) * $d + r] + u[(c + 1) * $d + r] - x[r] - u[r]
        });
        match j.try_inverse() {
            None => (0.0, false),
            Some(inv) => {
                let grad = (jd - j) * inv;
                let strain = (grad + grad.transpose()) * 0.5;
                (
                    largest!(strain, $floor),
                    j.determinant() * jd.determinant() <= 0.0,
                )
            }
        }
    }};
}

/// The largest principal strain (absolute value) of a cell and whether its
/// deformed shape is inverted; `x`, `u`: `dim` values per vertex. A Q1 cell
/// (or prism, pyramid): the strain at its centre, inverted where `det J` of
/// `x + u` has the other sign than that of `x` at a Gauss point. A strain
/// not above `floor` may be returned as 0 (0: always the strain).
pub fn cell_deformation(dim: usize, x: &[f64], u: &[f64], floor: f64) -> (f64, bool) {
    if x.len() != dim * (dim + 1) {
        return q1_deformation(dim, x, u, floor);
    }
    if dim == 2 {
        deformation!(2, x, u, floor)
    } else {
        deformation!(3, x, u, floor)
    }
}

fn q1_deformation(dim: usize, x: &[f64], u: &[f64], floor: f64) -> (f64, bool) {
    let k = x.len() / dim;
    let g = element::centre_gradients(dim, x);
    let mut strain = SMatrix::<f64, 3, 3>::zeros();
    for a in 0..k {
        for i in 0..dim {
            for j in 0..dim {
                let v = 0.5 * u[a * dim + i] * g[a * dim + j];
                strain[(i, j)] += v;
                strain[(j, i)] += v;
            }
        }
    }
    let largest = largest!(strain, floor);
    let moved: Vec<f64> = x.iter().zip(u).map(|(a, b)| a + b).collect();
    let inverted = element::jacobians(dim, x)
        .iter()
        .zip(element::jacobians(dim, &moved))
        .any(|((_, d0), (_, d1))| d0 * d1 <= 0.0);
    (largest, inverted)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stretch_and_inversion() {
        let x = [0.0, 0.0, 1.0, 0.0, 0.0, 1.0];
        // u = (0.1 x, 0): 10% strain, not inverted.
        let (e, inv) = cell_deformation(2, &x, &[0.0, 0.0, 0.1, 0.0, 0.0, 0.0], 0.0);
        assert!((e - 0.1).abs() < 1e-14 && !inv);
        // A rigid rotation by a small angle: strain of second order only.
        let t: f64 = 1e-4;
        let u: Vec<f64> = x
            .chunks(2)
            .flat_map(|p| {
                [
                    p[0] * (t.cos() - 1.0) - p[1] * t.sin(),
                    p[0] * t.sin() + p[1] * (t.cos() - 1.0),
                ]
            })
            .collect();
        assert!(cell_deformation(2, &x, &u, 0.0).0 < 1e-7);
        // Push vertex 1 across the opposite edge: inverted.
        let (_, inv) = cell_deformation(2, &x, &[0.0, 0.0, -1.5, 0.0, 0.0, 0.0], 0.0);
        assert!(inv);
        let x3 = [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0];
        let mut u3 = [0.0; 12];
        u3[11] = -0.2; // vertex 3 down by 0.2: 20% compression
        let (e, inv) = cell_deformation(3, &x3, &u3, 0.0);
        assert!((e - 0.2).abs() < 1e-14 && !inv);
        // A floor below the strain changes nothing; one above its bound
        // (the Frobenius norm, 0.2 here) may return 0, the inversion still told.
        assert!((cell_deformation(3, &x3, &u3, 0.19).0 - 0.2).abs() < 1e-14);
        assert_eq!(cell_deformation(3, &x3, &u3, 0.25).0, 0.0);
        let (e, inv) = cell_deformation(2, &x, &[0.0, 0.0, -1.5, 0.0, 0.0, 0.0], 10.0);
        assert!(e == 0.0 && inv);
    }
}
