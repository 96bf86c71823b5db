//! The cantilever column of the statics tests, also compiled into the cantilever bench and the
//! core's statics tests (`benches/cantilever.rs`, `tests/arc_length.rs` and
//! `tests/validation_statics.rs` include this file; it names only `crate::model` and
//! `crate::section`, which they bring into scope).

use crate::model::ModelBuilder;
use crate::section::BeamProps;

/// A column of length 1 m along x in `n` beams (`b0` … from node `n0` to `n{n}`, orientation
/// vector y), clamped at `n0`, with the dead force `tip` at `n{n}`: EI_y = 1 N·m², EI_z = `eiz`,
/// GJ = 1 N·m², EA = 1e7 N (EA L²/EI = 1e7: extensibility negligible), Euler–Bernoulli.
pub fn column(n: usize, eiz: f64, tip: [f64; 3]) -> ModelBuilder {
    let props = BeamProps {
        ea: 1e7,
        gj: 1.0,
        eiy: 1.0,
        eiz,
        ..Default::default()
    };
    let mut b = ModelBuilder::new("column");
    let (end, orient) = ([1.0, 0.0, 0.0], Some([0.0, 1.0, 0.0]));
    b.add_beam_chain("", [0.0; 3], end, n, orient, Some(props))
        .expect("a valid chain");
    b.fix("n0", None).expect("the first node");
    b.add_load(&format!("n{n}"), tip, [0.0; 3])
        .expect("the last node");
    b
}
