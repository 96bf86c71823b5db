//! Results of `flexmbd simulate`: text summary, JSON and CSV files (docs/simulation.md).

use crate::stream_json::{Seq, Sorted};
use flexmbd_core::results::{element_results, node_results};
use flexmbd_core::simulation::{Simulation, Stopped};
use flexmbd_core::Model;
use serde::ser::{Serialize, SerializeMap, Serializer};
use serde_json::{json, Value};
use std::fmt::Write as _;
use std::path::Path;

/// The JSON document of a run (complete, or stopped with `stopped`).
pub fn sim_json(model: &Model, file: &str, sim: &Simulation, stopped: Option<&Stopped>) -> Value {
    serde_json::to_value(SimDoc {
        model,
        file,
        sim,
        stopped,
    })
    .expect("a simulation serialises")
}

/// The JSON document of [`sim_json`] as it is serialised, streamed frame by frame and node by
/// node without a tree of the whole (as `modes_report::ModesDoc`). Keys in the tree's sorted
/// order: the same text.
pub struct SimDoc<'a> {
    /// The model simulated.
    pub model: &'a Model,
    /// The model file, as given.
    pub file: &'a str,
    /// The run.
    pub sim: &'a Simulation,
    /// Where and why the run stopped early, if it did.
    pub stopped: Option<&'a Stopped>,
}

impl Serialize for SimDoc<'_> {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let model = self.model;
        let mut m = s.serialize_map(Some(7))?;
        m.serialize_entry("analysis", "simulate")?;
        m.serialize_entry("complete", &self.stopped.is_none())?;
        m.serialize_entry("file", self.file)?;
        m.serialize_entry(
            "frames",
            &Seq(|| self.sim.frames.iter().map(|f| FrameDoc { model, f })),
        )?;
        m.serialize_entry("model", &model.name)?;
        m.serialize_entry("stats", &Sorted(&self.sim.stats))?;
        m.serialize_entry(
            "stopped",
            &self
                .stopped
                .map(|s| json!({"t": s.t, "reason": s.reason, "hint": s.hint})),
        )?;
        m.end()
    }
}

/// One output frame of [`SimDoc`].
struct FrameDoc<'a> {
    model: &'a Model,
    f: &'a flexmbd_core::simulation::Frame,
}

impl Serialize for FrameDoc<'_> {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let (model, f) = (self.model, self.f);
        let step = f.as_step();
        let mut m = s.serialize_map(Some(4))?;
        let elements = element_results(model, &step);
        m.serialize_entry("elements", &Seq(|| elements.iter().map(Sorted)))?;
        drop(elements);
        m.serialize_entry("energy", &Sorted(&f.energy))?;
        let nodes = node_results(model, &step);
        let vel = f.node_velocities(model);
        m.serialize_entry(
            "nodes",
            &Seq(|| {
                nodes.iter().zip(&vel).map(|(n, (v, w))| {
                    let mut o = serde_json::to_value(n).unwrap_or(Value::Null);
                    if let Value::Object(m) = &mut o {
                        m.insert("velocity".into(), json!(v));
                        m.insert("angular_velocity".into(), json!(w));
                    }
                    o
                })
            }),
        )?;
        m.serialize_entry("t", &f.t)?;
        m.end()
    }
}

/// The text summary: energies at the output times (at most about 40 rows) and the counts.
pub fn sim_text(model: &Model, file: &str, sim: &Simulation, stopped: Option<&Stopped>) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "Time simulation of {} ({file})", model.name);
    let st = &sim.stats;
    let _ = writeln!(
        s,
        "{} steps ({} rejected, {} Newton failures, {} Newton iterations, {} matrix updates); step {:.3e} … {:.3e} s",
        st.steps,
        st.rejected,
        st.newton_failures,
        st.newton_iterations,
        st.matrix_updates,
        st.min_step,
        st.max_step
    );
    let _ = writeln!(
        s,
        "largest constraint residual {:.3e}; largest energy balance error {:.3e} J",
        st.max_constraint_residual, st.max_energy_error
    );
    let _ = writeln!(
        s,
        "\n{:>12} {:>13} {:>13} {:>13} {:>13} {:>13} {:>13}",
        "t [s]",
        "kinetic [J]",
        "strain [J]",
        "W_ext [J]",
        "W_presc [J]",
        "dissip. [J]",
        "balance [J]"
    );
    let n = sim.frames.len();
    let every = n.div_ceil(40).max(1);
    for (k, f) in sim.frames.iter().enumerate() {
        if k % every != 0 && k + 1 != n {
            continue;
        }
        let e = &f.energy;
        let _ = writeln!(
            s,
            "{:>12.6} {:>13.6e} {:>13.6e} {:>13.6e} {:>13.6e} {:>13.6e} {:>13.3e}",
            f.t,
            e.kinetic,
            e.strain,
            e.external_work,
            e.prescribed_work,
            e.dissipated,
            e.balance_error
        );
    }
    if let Some(last) = sim.frames.last() {
        let _ = writeln!(s, "\nNodes at t = {:.6} s", last.t);
        let _ = writeln!(
            s,
            "{:<12} {:>13} {:>13} {:>13} {:>13} {:>13} {:>13}",
            "node", "x [m]", "y [m]", "z [m]", "vx [m/s]", "vy [m/s]", "vz [m/s]"
        );
        let vel = last.node_velocities(model);
        for (n, (v, _)) in node_results(model, &last.as_step()).iter().zip(vel) {
            let p = n.position;
            let _ = writeln!(
                s,
                "{:<12} {:>13.6e} {:>13.6e} {:>13.6e} {:>13.6e} {:>13.6e} {:>13.6e}",
                n.node, p[0], p[1], p[2], v[0], v[1], v[2]
            );
        }
    }
    if let Some(stop) = stopped {
        let _ = writeln!(
            s,
            "\nSTOPPED at t = {:.6e} s: {}. {}. The results above are those up to that time.",
            stop.t, stop.reason, stop.hint
        );
    }
    s
}

/// Write `energy.csv`, `nodes.csv` and `elements.csv` (long format: one row per output time
/// and node or element) into `dir`.
pub fn write_sim_csv(dir: &Path, model: &Model, sim: &Simulation) -> std::io::Result<()> {
    let mut energy =
        String::from("t,kinetic,strain,external_work,prescribed_work,dissipated,balance_error\n");
    let mut nodes =
        String::from("t,node,x,y,z,ux,uy,uz,rx,ry,rz,vx,vy,vz,wx,wy,wz,fx,fy,fz,mx,my,mz\n");
    let mut elements = String::from("t,element,mode,e,sigma\n");
    let opt = |v: Option<[f64; 3]>| match v {
        Some(a) => format!("{:e},{:e},{:e}", a[0], a[1], a[2]),
        None => ",,".to_string(),
    };
    for f in &sim.frames {
        let e = &f.energy;
        let _ = writeln!(
            energy,
            "{:e},{:e},{:e},{:e},{:e},{:e},{:e}",
            f.t,
            e.kinetic,
            e.strain,
            e.external_work,
            e.prescribed_work,
            e.dissipated,
            e.balance_error
        );
        let step = f.as_step();
        for (n, (v, w)) in node_results(model, &step)
            .iter()
            .zip(f.node_velocities(model))
        {
            let _ = writeln!(
                nodes,
                "{:e},{},{},{},{},{},{},{},{}",
                f.t,
                n.node,
                opt(Some(n.position)),
                opt(Some(n.displacement)),
                opt(n.rotation),
                opt(Some(v)),
                opt(w),
                opt(n.reaction_force),
                opt(n.reaction_moment)
            );
        }
        for el in element_results(model, &step) {
            for (k, (ek, sk)) in el.e.iter().zip(&el.sigma).enumerate() {
                let _ = writeln!(
                    elements,
                    "{:e},{},{},{:e},{:e}",
                    f.t,
                    el.element,
                    k + 1,
                    ek,
                    sk
                );
            }
        }
    }
    std::fs::write(dir.join("energy.csv"), energy)?;
    std::fs::write(dir.join("nodes.csv"), nodes)?;
    std::fs::write(dir.join("elements.csv"), elements)?;
    Ok(())
}
