//! Short lists, one per item (an element's free coordinates, its constrained rows), held in
//! one array: a `Vec` per item takes 24 bytes even when empty, and its own allocation.

/// One list per item, in item order ([`Lists::push`], [`Lists::of`]).
#[derive(Clone, Debug)]
pub(crate) struct Lists<T> {
    items: Vec<T>,
    /// Start of each list in `items` (lists + 1).
    start: Vec<u32>,
}

impl<T: Copy> Lists<T> {
    /// No lists, room for `n` of them.
    pub(crate) fn with_capacity(n: usize) -> Self {
        let mut start = Vec::with_capacity(n + 1);
        start.push(0);
        Self {
            items: Vec::new(),
            start,
        }
    }

    /// Appends the next list.
    pub(crate) fn push(&mut self, list: impl IntoIterator<Item = T>) {
        self.items.extend(list);
        self.start
            .push(u32::try_from(self.items.len()).expect("fewer than 2³² entries in all lists"));
    }

    /// Shrinks the arrays to their size (no more lists).
    pub(crate) fn finish(&mut self) {
        self.items.shrink_to_fit();
        self.start.shrink_to_fit();
    }

    /// List `i`.
    #[inline]
    pub(crate) fn of(&self, i: usize) -> &[T] {
        &self.items[self.start[i] as usize..self.start[i + 1] as usize]
    }

    /// Number of lists.
    pub(crate) fn len(&self) -> usize {
        self.start.len() - 1
    }
}
