//! Reading a model file in process: `cargo bench -p flexmbd-io --bench read_model -- FILE ...`
//! (issue 14: a model of 10^5 beams read in under 2 s). Per file (SPACAR `.dat` or TOML), the
//! best of three runs of each stage, wall time [s]: `text` the file into memory; `parse` the
//! text (`.dat`: the SPACAR reader and its checks; TOML: the TOML parser into the model
//! document); `build` into the model with its settings as `flexmbd static` and `modes` do
//! (`.dat`: the mapping to the static model and its build, `SpacarModel::to_model_file`;
//! TOML: `ModelSpec::build_file`). One JSON
//! line per file; `bench/strip_files.py --read-bench` runs it on the strip files. The
//! allocator is the binary's (mimalloc), so the figures are those of the `flexmbd` process.

use std::time::Instant;

#[global_allocator]
static GLOBAL: mimalloc::MiMalloc = mimalloc::MiMalloc;

/// The best of three runs of `f` [s], and its last result.
fn best<T>(mut f: impl FnMut() -> T) -> (f64, T) {
    let mut best = f64::INFINITY;
    let mut last = None;
    for _ in 0..3 {
        let t = Instant::now();
        let r = f();
        best = best.min(t.elapsed().as_secs_f64());
        last = Some(r);
    }
    (best, last.expect("three runs"))
}

fn main() {
    let files: Vec<String> = std::env::args()
        .skip(1)
        .filter(|a| !a.starts_with("--"))
        .collect();
    if files.is_empty() {
        eprintln!("usage: cargo bench -p flexmbd-io --bench read_model -- FILE.dat|FILE.toml ...");
        std::process::exit(2);
    }
    for file in files {
        let path = std::path::Path::new(&file);
        let (t_text, text) = best(|| std::fs::read_to_string(path));
        let text = match text {
            Ok(t) => t,
            Err(e) => {
                eprintln!("{file}: {e}");
                std::process::exit(4);
            }
        };
        let dat = path
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("dat"));
        let fail = |e: String| -> ! {
            eprintln!("{e}");
            std::process::exit(2)
        };
        // .dat: parse = the SPACAR reader and its checks, build = the mapping to the static
        // model and its build (`SpacarModel::to_model_file`, as `flexmbd static FILE.dat`)
        let (t_parse, t_build, model) = if dat {
            let (t_parse, m) = best(|| flexmbd_io::parse_dat(&text, &file));
            let m = m.unwrap_or_else(|e| fail(e.to_string()));
            let (t_build, f) = best(|| m.to_model_file());
            let (f, _) = f.unwrap_or_else(|e| fail(e.to_string()));
            (t_parse, t_build, f.model)
        } else {
            let (t_parse, spec) = best(|| flexmbd_io::model_toml::parse_spec(&text, &file));
            let spec = spec.unwrap_or_else(|e| fail(e.to_string()));
            let (t_build, f) = best(|| spec.build_file());
            let f = f.unwrap_or_else(|e| fail(format!("{file}: {e}")));
            (t_parse, t_build, f.model)
        };
        println!(
            "{{\"file\": {:?}, \"nodes\": {}, \"elements\": {}, \"text_s\": {t_text:.4}, \"parse_s\": {t_parse:.4}, \"build_s\": {t_build:.4}, \"read_s\": {:.4}}}",
            path.file_name().map_or(file.clone(), |n| n.to_string_lossy().into_owned()),
            model.nodes.len(),
            model.elements.len(),
            t_text + t_parse + t_build
        );
    }
}
