//! Pieces for JSON documents serialised straight from the results, without a serde_json tree
//! of the whole document (ten times the text for a large model): a sequence from an iterator
//! made on demand, and a value whose keys are sorted as a tree's maps sort them, so that a
//! streamed document has the same bytes as the tree it replaces.

use serde::ser::{Error as _, Serialize, Serializer};

/// A sequence serialised from an iterator made on demand (nothing collected).
pub(crate) struct Seq<F>(pub(crate) F);

impl<F, I> Serialize for Seq<F>
where
    F: Fn() -> I,
    I: Iterator,
    I::Item: Serialize,
{
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.collect_seq((self.0)())
    }
}

/// A value serialised through its own small serde_json tree, whose maps sort their keys (the
/// order of the document's tree before it was streamed; one item at a time).
pub(crate) struct Sorted<T>(pub(crate) T);

impl<T: Serialize> Serialize for Sorted<T> {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        serde_json::to_value(&self.0)
            .map_err(S::Error::custom)?
            .serialize(s)
    }
}
