//! Element connectivity stored flat ([`Cells`]), with CSR offsets only
//! when the elements differ in size.

use serde::{Deserialize, Serialize};

/// Element connectivity: node indices of each element, stored flat. While
/// every element has the same number of nodes (the `stride`) there are no
/// offsets; the first element of another size switches to CSR offsets
/// (`offsets[e]..offsets[e + 1]` in `nodes`). Equality compares the elements,
/// not the storage.
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub struct Cells {
    nodes: Vec<usize>,
    /// Nodes per element while all have the same count (0: empty, or mixed).
    stride: usize,
    /// `len() + 1` offsets when mixed, else empty.
    offsets: Vec<usize>,
}

impl PartialEq for Cells {
    fn eq(&self, o: &Cells) -> bool {
        self.len() == o.len() && self.iter().zip(o.iter()).all(|(a, b)| a == b)
    }
}

impl Cells {
    /// An empty list.
    pub fn new() -> Cells {
        Cells::default()
    }

    /// Elements of `k` nodes each, from their flat connectivity.
    pub fn uniform(nodes: Vec<usize>, k: usize) -> Cells {
        assert!(
            k > 0 && nodes.len().is_multiple_of(k),
            "{} nodes in elements of {k}",
            nodes.len()
        );
        Cells {
            stride: if nodes.is_empty() { 0 } else { k },
            nodes,
            offsets: Vec::new(),
        }
    }

    pub fn len(&self) -> usize {
        self.nodes
            .len()
            .checked_div(self.stride)
            .unwrap_or_else(|| self.offsets.len().saturating_sub(1))
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The common node count of the elements, if they all have the same (and there are some).
    pub fn stride(&self) -> Option<usize> {
        (self.stride > 0).then_some(self.stride)
    }

    /// The largest node count of an element (0 if empty).
    pub fn max_nodes(&self) -> usize {
        if self.stride > 0 {
            self.stride
        } else {
            self.offsets
                .windows(2)
                .map(|w| w[1] - w[0])
                .max()
                .unwrap_or(0)
        }
    }

    /// The nodes of element `e`.
    #[inline]
    pub fn get(&self, e: usize) -> &[usize] {
        if self.stride > 0 {
            &self.nodes[e * self.stride..(e + 1) * self.stride]
        } else {
            &self.nodes[self.offsets[e]..self.offsets[e + 1]]
        }
    }

    /// Appends an element.
    pub fn push(&mut self, element: &[usize]) {
        let k = element.len();
        debug_assert!(k > 0, "an element without nodes");
        if self.nodes.is_empty() {
            self.stride = k;
            self.offsets.clear();
        } else if self.stride > 0 && self.stride != k {
            // First element of another size: switch to offsets.
            let s = self.stride;
            self.offsets = (0..=self.nodes.len() / s).map(|e| e * s).collect();
            self.stride = 0;
        }
        self.nodes.extend_from_slice(element);
        if self.stride == 0 {
            self.offsets.push(self.nodes.len());
        }
    }

    /// Every node of every element, element after element.
    pub fn nodes(&self) -> &[usize] {
        &self.nodes
    }

    /// Mutable access to the node indices (to renumber them).
    pub fn nodes_mut(&mut self) -> &mut [usize] {
        &mut self.nodes
    }

    /// The elements in order.
    pub fn iter(&self) -> CellIter<'_> {
        CellIter {
            cells: self,
            next: 0,
        }
    }
}

/// Iterator over the elements of a [`Cells`].
pub struct CellIter<'a> {
    cells: &'a Cells,
    next: usize,
}

impl<'a> Iterator for CellIter<'a> {
    type Item = &'a [usize];
    #[inline]
    fn next(&mut self) -> Option<&'a [usize]> {
        if self.next < self.cells.len() {
            self.next += 1;
            Some(self.cells.get(self.next - 1))
        } else {
            None
        }
    }
    fn size_hint(&self) -> (usize, Option<usize>) {
        let n = self.cells.len() - self.next;
        (n, Some(n))
    }
}

impl ExactSizeIterator for CellIter<'_> {}

impl<'a> IntoIterator for &'a Cells {
    type Item = &'a [usize];
    type IntoIter = CellIter<'a>;
    fn into_iter(self) -> CellIter<'a> {
        self.iter()
    }
}

impl FromIterator<Vec<usize>> for Cells {
    fn from_iter<I: IntoIterator<Item = Vec<usize>>>(it: I) -> Cells {
        let mut c = Cells::new();
        for e in it {
            c.push(&e);
        }
        c
    }
}
