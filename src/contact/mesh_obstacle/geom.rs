//! Small vector algebra in 3D (a 2D obstacle lies in z = 0) and the closest
//! point of a segment or a triangle, with the feature it lies on.

pub(super) type V3 = [f64; 3];

pub(super) fn sub(a: &V3, b: &V3) -> V3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

pub(super) fn add(a: &V3, b: &V3) -> V3 {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

pub(super) fn scale(a: &V3, s: f64) -> V3 {
    [a[0] * s, a[1] * s, a[2] * s]
}

/// `a + s b`.
pub(super) fn axpy(a: &V3, s: f64, b: &V3) -> V3 {
    [a[0] + s * b[0], a[1] + s * b[1], a[2] + s * b[2]]
}

pub(super) fn dot(a: &V3, b: &V3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

pub(super) fn cross(a: &V3, b: &V3) -> V3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

pub(super) fn norm(a: &V3) -> f64 {
    dot(a, a).sqrt()
}

/// `a / |a|`, or `a` itself when it is zero.
pub(super) fn unit(a: &V3) -> V3 {
    let n = norm(a);
    if n > 0.0 {
        scale(a, 1.0 / n)
    } else {
        *a
    }
}

/// The angle between `a` and `b` (radians, in [0, pi]); robust near 0 and pi.
pub(super) fn angle(a: &V3, b: &V3) -> f64 {
    norm(&cross(a, b)).atan2(dot(a, b))
}

/// Where on an element its closest point lies: one of its corners, one of
/// its edges (edge `k` joins corners `k` and `k + 1 mod 3`; triangles
/// only), or its interior (a segment's interior, a triangle's face).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Feature {
    Vertex(usize),
    Edge(usize),
    Face,
}

/// The closest point to `p` of the segment `[a, b]` (of nonzero length).
pub(super) fn closest_on_segment(p: &V3, a: &V3, b: &V3) -> (V3, Feature) {
    let ab = sub(b, a);
    let t = dot(&sub(p, a), &ab) / dot(&ab, &ab);
    if t <= 0.0 {
        (*a, Feature::Vertex(0))
    } else if t >= 1.0 {
        (*b, Feature::Vertex(1))
    } else {
        (axpy(a, t, &ab), Feature::Face)
    }
}

/// The closest point to `p` of the triangle `abc` (of nonzero area), by
/// the Voronoi regions of its corners, edges and face (Ericson,
/// Real-Time Collision Detection, 2005, section 5.1.5).
pub(super) fn closest_on_triangle(p: &V3, a: &V3, b: &V3, c: &V3) -> (V3, Feature) {
    let ab = sub(b, a);
    let ac = sub(c, a);
    let ap = sub(p, a);
    let d1 = dot(&ab, &ap);
    let d2 = dot(&ac, &ap);
    if d1 <= 0.0 && d2 <= 0.0 {
        return (*a, Feature::Vertex(0));
    }
    let bp = sub(p, b);
    let d3 = dot(&ab, &bp);
    let d4 = dot(&ac, &bp);
    if d3 >= 0.0 && d4 <= d3 {
        return (*b, Feature::Vertex(1));
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        let v = d1 / (d1 - d3);
        return (axpy(a, v, &ab), Feature::Edge(0));
    }
    let cp = sub(p, c);
    let d5 = dot(&ab, &cp);
    let d6 = dot(&ac, &cp);
    if d6 >= 0.0 && d5 <= d6 {
        return (*c, Feature::Vertex(2));
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        let w = d2 / (d2 - d6);
        return (axpy(a, w, &ac), Feature::Edge(2));
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0 {
        let w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return (axpy(b, w, &sub(c, b)), Feature::Edge(1));
    }
    let denom = 1.0 / (va + vb + vc);
    let v = vb * denom;
    let w = vc * denom;
    (add(&axpy(a, v, &ab), &scale(&ac, w)), Feature::Face)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Brute force: the closest of a fine grid of barycentric points.
    fn brute(p: &V3, a: &V3, b: &V3, c: &V3) -> f64 {
        let n = 400;
        let mut best = f64::INFINITY;
        for i in 0..=n {
            for j in 0..=n - i {
                let (u, v) = (i as f64 / n as f64, j as f64 / n as f64);
                let q = add(&axpy(a, u, &sub(b, a)), &scale(&sub(c, a), v));
                best = best.min(norm(&sub(p, &q)));
            }
        }
        best
    }

    #[test]
    fn triangle_regions_match_brute_force() {
        let (a, b, c) = ([0.0, 0.0, 0.0], [1.0, 0.2, 0.1], [0.3, 0.9, -0.2]);
        let probes: [V3; 8] = [
            [-0.5, -0.5, 0.3],
            [1.5, 0.0, 0.0],
            [0.2, 1.5, 0.0],
            [0.5, -0.5, 0.5],
            [0.9, 0.9, 0.0],
            [-0.4, 0.5, -0.3],
            [0.4, 0.3, 0.7],
            [0.4, 0.3, -0.7],
        ];
        let want = [
            Feature::Vertex(0),
            Feature::Vertex(1),
            Feature::Vertex(2),
            Feature::Edge(0),
            Feature::Edge(1),
            Feature::Edge(2),
            Feature::Face,
            Feature::Face,
        ];
        for (p, w) in probes.iter().zip(want) {
            let (q, f) = closest_on_triangle(p, &a, &b, &c);
            assert_eq!(f, w, "feature of {p:?}");
            let d = norm(&sub(p, &q));
            let bf = brute(p, &a, &b, &c);
            // The grid spacing bounds the brute-force error.
            assert!(d <= bf + 1e-12 && bf - d < 3e-3, "{p:?}: {d} vs {bf}");
        }
    }

    #[test]
    fn segment_regions() {
        let (a, b) = ([0.0, 0.0, 0.0], [2.0, 0.0, 0.0]);
        assert_eq!(
            closest_on_segment(&[-1.0, 1.0, 0.0], &a, &b),
            (a, Feature::Vertex(0))
        );
        assert_eq!(
            closest_on_segment(&[3.0, 1.0, 0.0], &a, &b),
            (b, Feature::Vertex(1))
        );
        assert_eq!(
            closest_on_segment(&[0.5, -1.0, 0.0], &a, &b),
            ([0.5, 0.0, 0.0], Feature::Face)
        );
    }
}
