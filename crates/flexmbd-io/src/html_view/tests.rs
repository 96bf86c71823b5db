//! Tests of the HTML viewer's data and page (the page in a browser: crates/flexmbd-cli/tests/
//! html_chromium.py).

use super::*;
use crate::parse_model;
use flexmbd_core::kinematics::advice::advise;
use flexmbd_core::kinematics::{check, CheckOptions};
use flexmbd_core::section::{BeamProps, Material, Shape};

const TWELVE: &str = include_str!("../../../../examples/twelve_truss.toml");
const SIX: &str = include_str!("../../../../examples/folded_sheet_guide_6.toml");
const STROKE: &str = include_str!("../../../../examples/parallel_leaf_stroke.toml");
const STRIP: &str = include_str!("../../../../examples/strip_f01.toml");

/// The page data of a check, as `flexmbd view --analysis check` makes it.
fn check_data(text: &str, name: &str) -> ViewData {
    let m = parse_model(text, name).expect("example model");
    let x = m.x0();
    let opts = CheckOptions::default();
    let a = check(&m, &m.partition, &x, &opts).expect("check");
    let advice = advise(&m, &m.partition, &x, &a, &opts, 6).expect("advice");
    let names = crate::report::generalised_names(&m, &m.partition.x, &m.partition.e);
    let c = Classification {
        analysis: &a,
        advice: &advice,
        generalised: &names,
        rank_tol: opts.rank_tol,
        screws: None,
        wires: &[],
    };
    view_data(&m, name, Some(&c), &ViewResults::Check)
}

fn static_data(steps: usize) -> (Model, ViewData) {
    let f = crate::parse_model_file(STROKE, "parallel_leaf_stroke.toml").expect("model");
    let opts = flexmbd_core::statics::StaticOptions {
        steps,
        ..Default::default()
    };
    let sol = flexmbd_core::statics::solve(&f.model, &opts, |_, _| {}).expect("statics");
    let d = view_data(
        &f.model,
        "parallel_leaf_stroke.toml",
        None,
        &ViewResults::Static(&sol),
    );
    (f.model, d)
}

fn modes_data() -> (Model, ViewData) {
    let f = crate::parse_model_file(STRIP, "strip_f01.toml").expect("model");
    let opts = flexmbd_core::statics::StaticOptions {
        steps: 1,
        ..Default::default()
    };
    let sol = flexmbd_core::statics::solve(&f.model, &opts, |_, _| {}).expect("statics");
    let step = sol.steps.last().expect("a step");
    let modal = flexmbd_core::dynamics::modes(&f.model, step, 4).expect("modes");
    let d = view_data(
        &f.model,
        "strip_f01.toml",
        None,
        &ViewResults::Modes {
            step,
            index: sol.steps.len() - 1,
            modal: &modal,
        },
    );
    (f.model, d)
}

/// The text of the `<script>` element with this id.
fn script_body<'a>(html: &'a str, id: &str) -> &'a str {
    let open = format!("id=\"{id}\">");
    let start = html
        .find(&open)
        .unwrap_or_else(|| panic!("no element {id}"))
        + open.len();
    let end = start + html[start..].find("</script>").expect("closing tag");
    &html[start..end]
}

#[test]
fn data_json_round_trips() {
    let (_, st) = static_data(3);
    let (_, md) = modes_data();
    for d in [
        check_data(TWELVE, "twelve_truss.toml"),
        check_data(SIX, "folded_sheet_guide_6.toml"),
        st,
        md,
    ] {
        let json = serde_json::to_string(&d).expect("serialise");
        // (serde_json's float_roundtrip feature, enabled for the tests, parses f64 exactly as
        // the browser's JSON.parse does)
        let back: ViewData = serde_json::from_str(&json).expect("parse back");
        assert_eq!(back, d, "{}", d.file);
        // and from the page, where < > & are escaped
        let html = view_html(&d).expect("page");
        let embedded: ViewData =
            serde_json::from_str(script_body(&html, "flexmbd-data")).expect("embedded JSON");
        assert_eq!(embedded, d, "{}", d.file);
    }
}

#[test]
fn twelve_truss_motion_and_self_stress() {
    let d = check_data(TWELVE, "twelve_truss.toml");
    let s = d.summary.as_ref().expect("summary");
    assert_eq!((s.table1_row, s.n_motions, s.n_self_stresses), (2, 1, 1));
    assert_eq!(d.frames.len(), 1);
    assert_eq!(d.animations.len(), 1);
    let a = &d.animations[0];
    assert_eq!(a.kind, "motion");
    // the supports s1..s4 stay, the top nodes move
    for (i, n) in d.nodes.iter().enumerate() {
        let u = &a.u[3 * i..3 * i + 3];
        let moves = u.iter().any(|v| v.abs() > 1e-6);
        assert_eq!(moves, n.name.starts_with('t'), "node {}", n.name);
        assert_eq!(n.fixed.len(), if n.name.starts_with('s') { 3 } else { 0 });
    }
    // the default amplitude: largest translation 10 % of the model size (3 for the 2 × 2 × 1 box)
    assert!((d.size - 3.0).abs() < 1e-12);
    let max = (0..d.nodes.len())
        .map(|i| {
            let u = &a.u[3 * i..3 * i + 3];
            a.scale * (u.iter().map(|v| (*v as f64).powi(2)).sum::<f64>()).sqrt()
        })
        .fold(0.0, f64::max);
    assert!((max - 0.3).abs() < 1e-6, "{max}");
    // the self-stress: every bar ±√3/6, with the signs of the paper (top square against the
    // legs)
    assert_eq!(d.fields.len(), 1);
    let f = &d.fields[0];
    assert_eq!((f.key.as_str(), f.diverging), ("self_stress_1", true));
    let v = &f.values[0];
    for (e, x) in d.elements.iter().zip(v) {
        let x = x.expect("every truss has a value") as f64;
        assert!((x.abs() - 3f64.sqrt() / 6.0).abs() < 1e-6, "{} {x}", e.name);
    }
    // the signs of `flexmbd check`: bars 1, 2, 5, 6, 9, 11 against 3, 4, 7, 8, 10, 12
    let sign: Vec<f64> = v.iter().map(|x| x.unwrap().signum() as f64).collect();
    for (k, s) in [
        1.0, 1.0, -1.0, -1.0, 1.0, 1.0, -1.0, -1.0, 1.0, -1.0, 1.0, -1.0,
    ]
    .iter()
    .enumerate()
    {
        assert_eq!(sign[k], s * sign[0], "bar {}", k + 1);
    }
    assert!((f.range[1] - 3f64.sqrt() / 6.0).abs() < 1e-6 && f.range[0] == -f.range[1]);
    // trusses: no section, no frame
    assert!(d
        .elements
        .iter()
        .all(|e| e.kind == ViewKind::Truss && e.section.is_none() && e.partition == "r"));
}

#[test]
fn folded_sheets_are_drawn_as_sheets() {
    let d = check_data(SIX, "folded_sheet_guide_6.toml");
    let s = d.summary.as_ref().expect("summary");
    assert_eq!((s.table1_row, s.n_motions, s.n_self_stresses), (3, 0, 1));
    assert!(d.animations.is_empty());
    assert!(!s.advice.is_empty() && s.advice.iter().all(|a| a.kind == "self_stress"));
    assert!(s.advice[0]
        .suggestions
        .iter()
        .any(|t| t.contains("release")));
    let mut sheets = 0;
    for e in &d.elements {
        if e.kind == ViewKind::Beam {
            let sec = e.section.as_ref().expect("section");
            // no section in the file: a sheet from the partition (in-plane bending rigid),
            // nominal width, minimum thickness, width along the orientation vector (local y)
            assert_eq!(sec.shape, SectionShape::Rectangle, "{}", e.name);
            assert_eq!(sec.source, "partition");
            assert!(sec.actual.is_none());
            assert!((sec.width - NOMINAL_SHEET_WIDTH * d.size).abs() < 1e-12);
            assert!((sec.thickness - MIN_THICKNESS * d.size).abs() < 1e-12);
            assert!(e.frame.is_some());
            sheets += 1;
        }
    }
    assert_eq!(sheets, 12);
    // the self-stress runs through every sheet (in-plane bending) and the platform (torsion)
    let v = &d.fields[0].values[0];
    for (e, x) in d.elements.iter().zip(v) {
        assert!(x.expect("value").abs() > 1e-3, "{} carries none", e.name);
    }
    let clamped = d.nodes.iter().filter(|n| {
        ["x", "y", "z"]
            .iter()
            .all(|x| n.fixed.iter().any(|f| f == x))
    });
    assert_eq!(clamped.count(), 6);
    assert_eq!(
        d.nodes.iter().find(|n| n.name == "c").expect("c").input,
        vec!["x".to_string()]
    );
}

#[test]
fn static_steps_and_stress_fields() {
    let (m, d) = static_data(4);
    assert_eq!(d.analysis, "static");
    assert_eq!(d.frames.len(), 5, "the unloaded state and 4 steps");
    assert_eq!(d.frames[0].load_factor, Some(0.0));
    assert_eq!(d.frames[4].load_factor, Some(1.0));
    // the platform p moves 5 mm along x at the end of the stroke
    let p = m.node_id("p").expect("p");
    let dx = d.frames[4].x[3 * p] as f64 - d.frames[0].x[3 * p] as f64;
    assert!((dx - 0.005).abs() < 1e-6, "{dx}");
    // unit Euler parameters in every frame
    for f in &d.frames {
        for q in f.q.chunks(4) {
            let n: f64 = q.iter().map(|v| (*v as f64).powi(2)).sum();
            assert!((n - 1.0).abs() < 1e-5);
        }
    }
    let keys: Vec<&str> = d.fields.iter().map(|f| f.key.as_str()).collect();
    assert!(
        keys.contains(&"max_stress") && keys.contains(&"sigma1"),
        "{keys:?}"
    );
    let ms = d
        .fields
        .iter()
        .find(|f| f.key == "max_stress")
        .expect("field");
    assert_eq!(ms.per, FieldPer::Frame);
    assert_eq!(ms.values.len(), 5);
    // no stress before loading, stress at the end; rigid bodies have none
    assert!(ms.values[0].iter().flatten().all(|v| v.abs() < 1.0));
    assert!(ms.values[4].iter().flatten().any(|v| *v > 1e6));
    for (e, v) in d.elements.iter().zip(&ms.values[4]) {
        assert_eq!(v.is_some(), e.kind == ViewKind::Beam, "{}", e.name);
    }
    // leaves with their real section: 20 mm × 0.3 mm, drawn at least MIN_THICKNESS thick
    for e in d.elements.iter().filter(|e| e.kind == ViewKind::Beam) {
        let s = e.section.as_ref().expect("section");
        assert_eq!(s.shape, SectionShape::Rectangle);
        let a = s.actual.expect("actual");
        assert!((a[0] - 0.02).abs() < 1e-12 && (a[1] - 0.0003).abs() < 1e-12);
        assert!((s.width - 0.02).abs() < 1e-12);
        assert!((s.thickness - (MIN_THICKNESS * d.size).max(0.0003)).abs() < 1e-12);
    }
    assert!(d.animations.is_empty() && d.summary.is_none());
}

#[test]
fn modes_animations_with_frequencies() {
    let (_, d) = modes_data();
    assert_eq!(d.analysis, "modes");
    assert_eq!(d.animations.len(), 4);
    // F01: the first bending frequency 40.90 Hz (docs/dynamics.md)
    let f1 = d.animations[0].value.expect("frequency");
    assert!((f1 - 40.9).abs() < 0.1, "{f1}");
    assert!(d.animations[0].detail.ends_with("Hz"));
    assert!(d
        .animations
        .windows(2)
        .all(|w| w[0].value.unwrap() <= w[1].value.unwrap()));
    let se = d
        .fields
        .iter()
        .find(|f| f.key == "strain_energy")
        .expect("field");
    assert_eq!(se.per, FieldPer::Animation);
    assert_eq!(se.values.len(), 4);
    // each mode's strain energy shares add up to 100 %
    for v in &se.values {
        let sum: f64 = v.iter().flatten().map(|x| *x as f64).sum();
        assert!((sum - 100.0).abs() < 0.1, "{sum}");
    }
}

#[test]
fn page_is_self_contained() {
    let d = check_data(TWELVE, "twelve_truss.toml");
    let html = view_html(&d).expect("page");
    // the markup and style outside the script elements load nothing
    let mut markup = String::new();
    let mut rest = html.as_str();
    while let Some(i) = rest.find("<script") {
        markup.push_str(&rest[..i]);
        let end = rest[i..].find("</script>").expect("closed") + i;
        // keep the opening tag: it must have no src attribute
        markup.push_str(&rest[i..i + rest[i..].find('>').expect("tag end") + 1]);
        rest = &rest[end..];
    }
    markup.push_str(rest);
    let lower = markup.to_ascii_lowercase();
    assert_eq!(
        lower.matches("<script").count(),
        5,
        "error capture, data, three, controls, viewer"
    );
    for bad in [
        " src=", " href=", "<link", "@import", "url(", "<iframe", "<img", "<object",
    ] {
        assert!(!lower.contains(bad), "the page contains `{bad}`");
    }
    // the viewer fetches nothing and imports only the Blob URLs it makes
    for bad in [
        "fetch(",
        "XMLHttpRequest",
        "new Worker",
        "from 'http",
        "import('http",
    ] {
        assert!(!VIEWER_JS.contains(bad), "viewer.js contains `{bad}`");
    }
    assert_eq!(
        ORBIT_JS.matches("from 'three'").count(),
        1,
        "the import the viewer rewrites"
    );
    assert!(
        !THREE_JS.contains("import "),
        "the module build imports nothing"
    );
    // the only URLs are namespace names inside three.js (never fetched)
    let allowed = ["http://www.w3.org/1999/xhtml"];
    for (i, _) in lower.match_indices("http") {
        let tail = &html[i..];
        if tail.starts_with("http://") || tail.starts_with("https://") {
            assert!(
                allowed.iter().any(|a| tail.starts_with(a)),
                "URL in the page: {}",
                &tail[..tail.len().min(60)]
            );
        }
    }
    // the three.js sources and licence are there, the viewer too
    assert!(html.contains("Three.js Authors"));
    assert!(html.contains("class OrbitControls"));
    assert!(html.contains("Permission is hereby granted"));
    assert!(html.contains("function hermite") || html.contains("Hermite"));
    assert!(html.contains(r#"<script type="module">"#));
    // all template markers are filled
    assert!(!html.contains("{{DATA}}") && !html.contains("{{VIEWER}}"));
}

#[test]
fn script_closing_tags_in_data_are_escaped() {
    let mut d = check_data(TWELVE, "twelve_truss.toml");
    d.title = "</script><script>alert(1)</script> <!-- {{DATA}} & more".into();
    d.file = "a</SCRIPT >b.toml".into();
    let html = view_html(&d).expect("page");
    // the script elements of the template, and no more
    let expected = TEMPLATE.matches("</script>").count();
    assert_eq!(
        html.to_ascii_lowercase().matches("</script").count(),
        expected
    );
    assert!(!script_body(&html, "flexmbd-data").contains('<'));
    let back: ViewData = serde_json::from_str(script_body(&html, "flexmbd-data")).expect("JSON");
    assert_eq!(back.title, d.title);
    assert_eq!(back.file, d.file);
    // the title element shows it as text
    assert!(html.contains("<title>&lt;/script&gt;&lt;script&gt;alert(1)&lt;/script&gt;"));
    // the one-pass fill leaves `{{DATA}}` inside the data alone
    assert_eq!(html.matches(r#"id="flexmbd-data""#).count(), 1);
}

#[test]
fn script_text_and_json_escapes() {
    assert_eq!(
        script_text("a</script>b</SCRIPT"),
        "a<\\/script>b<\\/SCRIPT"
    );
    assert_eq!(script_text("x < y && y > z"), "x < y && y > z");
    assert_eq!(
        script_json(r#"{"a":"</b>&"}"#),
        r#"{"a":"\u003c/b\u003e\u0026"}"#
    );
    let v: serde_json::Value = serde_json::from_str(&script_json(r#"{"a":"</b>&"}"#)).unwrap();
    assert_eq!(v["a"], "</b>&");
    // the vendored sources need no escaping and have no HTML comment openers
    for src in [THREE_JS, ORBIT_JS, VIEWER_JS] {
        let l = src.to_ascii_lowercase();
        assert!(!l.contains("</script") && !l.contains("<!--") && !l.contains("<script"));
    }
    assert_eq!(
        fill(
            "<{{A}}|{{B}}|{{C}}>",
            &[("A", "{{B}}".into()), ("B", "b".into())]
        ),
        "<{{B}}|b|{{C}}>"
    );
}

#[test]
fn sections_from_section_data() {
    let steel = Material {
        e: 210e9,
        g: 80e9,
        rho: 7800.0,
    };
    let beam = |shape: Shape| {
        let mut b = flexmbd_core::elements::Beam::new(
            [0, 1],
            [0.0; 3],
            [0.1, 0.0, 0.0],
            Some([0.0, 1.0, 0.0]),
        )
        .expect("beam");
        b.set_props(BeamProps::from_section(&steel, &shape, false));
        b
    };
    let size = 0.1;
    let r = beam_section(
        &beam(Shape::Rectangle { w: 0.02, t: 0.001 }),
        "ffffff",
        size,
    );
    assert_eq!(r.shape, SectionShape::Rectangle);
    assert_eq!(r.actual, Some([0.02, 0.001]));
    assert!((r.width - 0.02).abs() < 1e-15);
    assert!((r.thickness - 0.001).abs() < 1e-15, "1 mm > 0.4 mm minimum");
    let thin = beam_section(
        &beam(Shape::Rectangle { w: 0.02, t: 0.0001 }),
        "ffffff",
        size,
    );
    assert!((thin.thickness - MIN_THICKNESS * size).abs() < 1e-15);
    let c = beam_section(&beam(Shape::Circle { d: 0.002 }), "ffffff", size);
    assert_eq!(c.shape, SectionShape::Round);
    assert!((c.width - 0.002).abs() < 1e-15 && c.actual.is_some());
    let w = beam_section(&beam(Shape::Circle { d: 0.0002 }), "ffffff", size);
    assert!((w.width - MIN_DIAMETER * size).abs() < 1e-15);
    let t = beam_section(
        &beam(Shape::Tube {
            d_out: 0.01,
            d_in: 0.008,
        }),
        "ffffff",
        size,
    );
    assert_eq!(t.shape, SectionShape::Tube);
    let a = t.actual.expect("actual");
    assert!(
        (a[0] - 0.01).abs() < 1e-12 && (a[1] - 0.008).abs() < 1e-9,
        "{a:?}"
    );
    // a square is a rectangle, not a circle
    let sq = beam_section(&beam(Shape::Rectangle { w: 0.01, t: 0.01 }), "ffffff", size);
    assert_eq!(sq.shape, SectionShape::Rectangle);
}

#[test]
fn sections_without_section_data() {
    let bare = |stiffness: [f64; 4]| {
        let mut b =
            flexmbd_core::elements::Beam::new([0, 1], [0.0; 3], [0.1, 0.0, 0.0], None).unwrap();
        b.stiffness = stiffness;
        b
    };
    let size = 1.0;
    // in-plane bending (ε5, ε6) rigid, out-of-plane free: a sheet, wide along local y
    let s = beam_section(&bare([0.0; 4]), "rfffrr", size);
    assert_eq!(
        (s.shape, s.source.as_str()),
        (SectionShape::Rectangle, "partition")
    );
    assert!(s.width > s.thickness);
    // the other way round: wide along local z
    let s = beam_section(&bare([0.0; 4]), "rfrrff", size);
    assert!(s.width < s.thickness);
    // a wire: all bending free
    let s = beam_section(&bare([0.0; 4]), "rfffff", size);
    assert_eq!(s.shape, SectionShape::Round);
    // stiffness given directly: EIz/EIy = (w/t)² = 100 → a sheet with w/t = 10
    let s = beam_section(&bare([1.0, 1.0, 1.0, 100.0]), "ffffff", size);
    assert_eq!(
        (s.shape, s.source.as_str()),
        (SectionShape::Rectangle, "stiffness")
    );
    assert!((s.width / s.thickness - 10.0).abs() < 1e-9);
    let s = beam_section(&bare([1.0, 1.0, 1.0, 1.0]), "ffffff", size);
    assert_eq!(s.shape, SectionShape::Round);
}

#[test]
fn significant_digits() {
    assert_eq!(significant(8.988675, 4), "8.989");
    assert_eq!(significant(148.26, 4), "148.3");
    assert_eq!(significant(0.012345, 3), "0.0123");
    assert_eq!(significant(123456.0, 4), "1.235e5");
    assert_eq!(significant(0.0, 4), "0");
}

#[test]
fn animation_scale_limits_translation_and_rotation() {
    // translation governs
    let s = animation_scale(&[[3.0, 4.0, 0.0]], &[[0.0, 0.0, 0.01]], 2.0);
    assert!((s - 0.1 * 2.0 / 5.0).abs() < 1e-15);
    // rotation governs
    let s = animation_scale(&[[1e-3, 0.0, 0.0]], &[[0.0, 2.0, 0.0]], 1.0);
    assert!((s - ANIMATION_ROTATION / 2.0).abs() < 1e-15);
    // nothing moves
    assert_eq!(animation_scale(&[[0.0; 3]], &[[0.0; 3]], 1.0), 1.0);
}

#[test]
fn inconsistent_data_is_refused() {
    let mut d = check_data(TWELVE, "twelve_truss.toml");
    d.frames[0].x.pop();
    let e = view_html(&d).expect_err("short frame");
    assert!(e.to_string().contains("frame 0"), "{e}");
    let mut d = check_data(TWELVE, "twelve_truss.toml");
    d.fields[0].values[0].push(Some(1.0));
    let e = view_html(&d).expect_err("long field");
    assert!(e.to_string().contains("self_stress_1"), "{e}");
    let mut d = check_data(TWELVE, "twelve_truss.toml");
    d.elements[3].nodes[1] = 99;
    assert!(view_html(&d).is_err());
}

#[test]
fn check_data_draws_the_twist_axis_and_the_fighting_lines() {
    // The cross-spring pivot (K04): its motion is the rotation about the y axis, where the leaf
    // planes cross, and its self-stress a pair of opposite forces on that line (every line of
    // both planes meets the y axis; the two spans of plane forces share only the forces on it).
    let text = include_str!("../../../../examples/cross_spring_pivot.toml");
    let f = crate::parse_model_file(text, "cross_spring_pivot.toml").expect("model");
    let m = &f.model;
    let c = flexmbd_core::kinematics::classify::classify(m, &Default::default()).expect("check");
    let names = crate::report::generalised_names(m, &c.partition.x, &c.partition.e);
    let cl = Classification {
        analysis: &c.analysis,
        advice: &c.advice,
        generalised: &names,
        rank_tol: 1.5e-8,
        screws: Some(&c.screws),
        wires: &c.wires,
    };
    let d = view_data(m, "cross_spring_pivot.toml", Some(&cl), &ViewResults::Check);
    let on_y = |l: &ViewScrewLine| {
        l.direction[1].abs() > 1.0 - 1e-12 && l.point[0].abs() < 1e-12 && l.point[2].abs() < 1e-12
    };
    let axes: Vec<&ViewScrewLine> = d
        .screw_lines
        .iter()
        .filter(|l| l.item == Some(0) && l.kind != "wire")
        .collect();
    assert_eq!(axes.len(), 1, "{:?}", d.screw_lines);
    assert!(axes[0].kind == "rotation" && on_y(axes[0]), "{:?}", axes[0]);
    let fights: Vec<&ViewScrewLine> = d
        .screw_lines
        .iter()
        .filter(|l| l.field.as_deref() == Some("self_stress_1"))
        .collect();
    assert_eq!(fights.len(), 2, "{:?}", d.screw_lines);
    assert!(
        fights.iter().all(|l| l.kind == "force" && on_y(l)),
        "{fights:?}"
    );
}

#[test]
fn check_data_draws_the_suggested_wires_with_their_motion() {
    // The five-wire guide without wire 5 (docs/kinematic-analysis.md, "A worked example"): one
    // motion, a rotation about the vertical line through (−0.05, 0); the wire with the largest
    // moment arm about it, 0.1 m, is wire 5 itself, from a5 = (0.05, 0.03, 0.01) to
    // g5 = (0.05, 0.08, 0.01): drawn as that segment (length 0.05 along y) with the motion.
    let text = include_str!("../../../../examples/wire_guide_5.toml");
    let mut spec = crate::parse_spec(text, "wire_guide_5.toml").expect("spec");
    spec.remove_element("w5").expect("w5");
    let f = spec.build_file().expect("model");
    let m = &f.model;
    let c = flexmbd_core::kinematics::classify::classify_intended(
        m,
        &Default::default(),
        &f.freedom,
        |_| {},
    )
    .expect("check");
    let names = crate::report::generalised_names(m, &c.partition.x, &c.partition.e);
    let cl = Classification {
        analysis: &c.analysis,
        advice: &c.advice,
        generalised: &names,
        rank_tol: 1.5e-8,
        screws: Some(&c.screws),
        wires: &c.wires,
    };
    let d = view_data(m, "wire_guide_5.toml", Some(&cl), &ViewResults::Check);
    let wires: Vec<&ViewScrewLine> = d.screw_lines.iter().filter(|l| l.kind == "wire").collect();
    assert!(!wires.is_empty(), "{:?}", d.screw_lines);
    assert!(wires
        .iter()
        .all(|l| l.item == Some(0) && l.length.is_some()));
    let w = wires[0];
    let end: Vec<f64> = (0..3)
        .map(|k| w.point[k] + w.length.unwrap() * w.direction[k])
        .collect();
    let near = |a: &[f64], b: &[f64]| a.iter().zip(b).all(|(x, y)| (x - y).abs() < 1e-12);
    assert!(near(&w.point, &[0.05, 0.03, 0.01]), "{w:?}");
    assert!(near(&end, &[0.05, 0.08, 0.01]), "{w:?}");
    assert!(w.label.contains("a5 to g5"), "{}", w.label);
    // and the twist axis of the same motion
    assert!(d
        .screw_lines
        .iter()
        .any(|l| l.item == Some(0) && l.kind == "rotation"));
}
