//! The search of a contact pair's master elements ([`super::mortar`],
//! [`super::mortar3d`]): an R-tree (`rstar`) of their bounding boxes, queried
//! with a slave element's box grown until it meets a master element the
//! caller accepts (facing, overlapping), then with the element swept along
//! its normal by that element's distance: the pairing is the brute-force
//! one's (the same rows, tested), at the cost of a few queries per slave
//! element.

use rstar::{RTree, RTreeObject, AABB};

/// One master element's bounding box.
struct Boxed {
    index: usize,
    lo: [f64; 3],
    hi: [f64; 3],
}

impl RTreeObject for Boxed {
    type Envelope = AABB<[f64; 3]>;
    fn envelope(&self) -> Self::Envelope {
        AABB::from_corners(self.lo, self.hi)
    }
}

/// The master elements by bounding box.
pub struct Search {
    tree: RTree<Boxed>,
    /// The diagonal of all the boxes together (the query stops growing
    /// beyond it).
    extent: f64,
}

/// The bounding box of points (2 or 3 coordinates each).
pub fn bounds<'a>(points: impl Iterator<Item = &'a [f64]>) -> ([f64; 3], [f64; 3]) {
    let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
    for p in points {
        for c in 0..3 {
            let v = p.get(c).copied().unwrap_or(0.0);
            lo[c] = lo[c].min(v);
            hi[c] = hi[c].max(v);
        }
    }
    (lo, hi)
}

impl Search {
    /// The tree of the boxes `(lo, hi)` of the master elements, by index.
    pub fn new(boxes: Vec<([f64; 3], [f64; 3])>) -> Search {
        let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
        for (l, h) in &boxes {
            for c in 0..3 {
                lo[c] = lo[c].min(l[c]);
                hi[c] = hi[c].max(h[c]);
            }
        }
        let extent = (0..3)
            .map(|c| (hi[c] - lo[c]).max(0.0).powi(2))
            .sum::<f64>()
            .sqrt();
        let items = boxes
            .into_iter()
            .enumerate()
            .map(|(index, (lo, hi))| Boxed { index, lo, hi })
            .collect();
        Search {
            tree: RTree::bulk_load(items),
            extent,
        }
    }

    fn within(&self, lo: [f64; 3], hi: [f64; 3], d: f64) -> Vec<usize> {
        let grow = |p: [f64; 3], s: f64| [p[0] + s, p[1] + s, p[2] + s];
        let env = AABB::from_corners(grow(lo, -d), grow(hi, d));
        self.tree
            .locate_in_envelope_intersecting(&env)
            .map(|b| b.index)
            .collect()
    }

    /// The master elements that `measure` accepts (returning their distance
    /// along the slave's normal) near a slave element (its points `x`,
    /// normal `n`, size `size`): a box grown from the element's until some
    /// master is accepted, then the element swept along its normal by that
    /// distance (and an element size more), both ways: every master element
    /// whose projection along n meets the slave element within that
    /// distance. In increasing index order.
    pub fn near(
        &self,
        x: &[[f64; 3]],
        n: [f64; 3],
        size: f64,
        mut measure: impl FnMut(usize) -> Option<f64>,
    ) -> Vec<usize> {
        let (lo, hi) = bounds(x.iter().map(|p| &p[..]));
        let mut d = size.max(1e-300);
        let far = loop {
            let dist = self
                .within(lo, hi, d)
                .into_iter()
                .filter_map(&mut measure)
                .map(f64::abs)
                .reduce(f64::max);
            if let Some(dist) = dist {
                break dist.max(d);
            }
            if d > 2.0 * self.extent {
                return Vec::new();
            }
            d *= 2.0;
        };
        let t = far + 2.0 * size;
        let swept: Vec<[f64; 3]> = x
            .iter()
            .flat_map(|p| {
                [
                    [p[0] + t * n[0], p[1] + t * n[1], p[2] + t * n[2]],
                    [p[0] - t * n[0], p[1] - t * n[1], p[2] - t * n[2]],
                ]
            })
            .collect();
        let (lo, hi) = bounds(swept.iter().map(|p| &p[..]));
        let mut found: Vec<usize> = self
            .within(lo, hi, size)
            .into_iter()
            .filter(|&i| measure(i).is_some())
            .collect();
        found.sort_unstable();
        found
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grows_until_it_finds_and_keeps_the_near_ones() {
        // Boxes along x at 0, 1, ..., 9; the slave box far above the 5th.
        let boxes: Vec<_> = (0..10)
            .map(|i| ([i as f64, 0.0, 0.0], [i as f64 + 1.0, 0.0, 0.0]))
            .collect();
        let s = Search::new(boxes);
        let x = [[5.2, 7.0, 0.0], [5.8, 7.0, 0.0]];
        let n = [0.0, -1.0, 0.0];
        let hit = |i: usize| (i == 5 || i == 6).then_some(7.0);
        assert_eq!(s.near(&x, n, 0.6, hit), vec![5, 6]);
        assert!(s.near(&x, n, 0.6, |_| None).is_empty());
    }
}
