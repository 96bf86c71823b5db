//! Blocks of values kept once however many items share them: the elements of a uniform leaf
//! or wire have the same stiffness block, and in a straight reference state the same
//! deformation Jacobian, bit for bit.

use std::collections::HashMap;
use std::hash::{DefaultHasher, Hash, Hasher};

/// Blocks of values in one array, each distinct one (bit for bit) stored once and named by an
/// id ([`DistinctBlocks::add`], [`DistinctBlocks::get`]).
pub(crate) struct DistinctBlocks {
    vals: Vec<f64>,
    /// Start of block id in `vals` (blocks + 1).
    start: Vec<usize>,
    /// The ids of the blocks by the hash of their bits (a list of candidates per hash); dropped
    /// by [`DistinctBlocks::finish`].
    seen: HashMap<u64, Vec<u32>>,
}

impl Default for DistinctBlocks {
    fn default() -> Self {
        Self {
            vals: Vec::new(),
            start: vec![0],
            seen: HashMap::new(),
        }
    }
}

impl DistinctBlocks {
    /// The id of `block`: that of an equal block added before (bit for bit), or a new one.
    pub(crate) fn add(&mut self, block: &[f64]) -> u32 {
        let mut h = DefaultHasher::new();
        block.len().hash(&mut h);
        block.iter().for_each(|v| v.to_bits().hash(&mut h));
        let candidates = self.seen.entry(h.finish()).or_default();
        let (vals, start) = (&self.vals, &self.start);
        let same = candidates.iter().copied().find(|&c| {
            let stored = &vals[start[c as usize]..start[c as usize + 1]];
            stored.len() == block.len()
                && stored
                    .iter()
                    .zip(block)
                    .all(|(x, y)| x.to_bits() == y.to_bits())
        });
        same.unwrap_or_else(|| {
            let id = u32::try_from(self.start.len() - 1).expect("fewer than 2³² blocks");
            self.vals.extend_from_slice(block);
            self.start.push(self.vals.len());
            candidates.push(id);
            id
        })
    }

    /// No more blocks: the search structure is released and the arrays shrunk to their size.
    pub(crate) fn finish(&mut self) {
        self.seen = HashMap::new();
        self.vals.shrink_to_fit();
        self.start.shrink_to_fit();
    }

    /// The values of block `id`.
    #[inline]
    pub(crate) fn get(&self, id: u32) -> &[f64] {
        let id = id as usize;
        &self.vals[self.start[id]..self.start[id + 1]]
    }
}
