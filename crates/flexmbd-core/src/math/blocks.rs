//! Blocks of values kept once however many items share them: the elements of a uniform leaf
//! or wire have the same stiffness block, bit for bit.

use super::lists::Lists;
use std::collections::HashMap;
use std::hash::{DefaultHasher, Hash, Hasher};

/// Blocks of values, each distinct one (bit for bit) stored once and named by an id, its
/// index among the stored blocks ([`DistinctBlocks::add`], [`DistinctBlocks::get`]).
pub(crate) struct DistinctBlocks {
    blocks: Lists<f64>,
    /// The ids of the blocks by the hash of their bits (a list of candidates per hash); dropped
    /// by [`DistinctBlocks::finish`].
    seen: HashMap<u64, Vec<u32>>,
}

impl Default for DistinctBlocks {
    fn default() -> Self {
        Self {
            blocks: Lists::with_capacity(0),
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
        let blocks = &self.blocks;
        let same = candidates.iter().copied().find(|&c| {
            let stored = blocks.of(c as usize);
            stored.len() == block.len()
                && stored
                    .iter()
                    .zip(block)
                    .all(|(x, y)| x.to_bits() == y.to_bits())
        });
        same.unwrap_or_else(|| {
            let id = u32::try_from(self.blocks.len()).expect("fewer than 2³² blocks");
            self.blocks.push(block.iter().copied());
            candidates.push(id);
            id
        })
    }

    /// No more blocks: the search structure is released and the arrays shrunk to their size.
    pub(crate) fn finish(&mut self) {
        self.seen = HashMap::new();
        self.blocks.finish();
    }

    /// The values of block `id`.
    #[inline]
    pub(crate) fn get(&self, id: u32) -> &[f64] {
        self.blocks.of(id as usize)
    }
}
