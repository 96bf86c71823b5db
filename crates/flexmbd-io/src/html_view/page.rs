//! The HTML page: the template with the data as JSON, the viewer and the vendored three.js
//! inlined, and the checks and escapes that keep the inlined text inert.

use super::document::{FieldPer, ViewData, ViewError};

/// Version of the vendored three.js (`assets/viewer/vendor/three/VENDORED.md`).
pub const THREE_VERSION: &str = "0.170.0";

pub(super) const TEMPLATE: &str = include_str!("../../assets/viewer/template.html");
pub(super) const VIEWER_JS: &str = include_str!("../../assets/viewer/viewer.js");
pub(super) const VIEWER_CSS: &str = include_str!("../../assets/viewer/viewer.css");
pub(super) const THREE_JS: &str =
    include_str!("../../assets/viewer/vendor/three/three.module.min.js");
pub(super) const ORBIT_JS: &str = include_str!("../../assets/viewer/vendor/three/OrbitControls.js");
pub(super) const THREE_LICENSE: &str = include_str!("../../assets/viewer/vendor/three/LICENSE");

/// The page: one self-contained HTML document.
pub fn view_html(data: &ViewData) -> Result<String, ViewError> {
    check_data(data)?;
    super::simulate::check_simulation(data)?;
    let json = script_json(&serde_json::to_string(data)?);
    let title = if data.title.is_empty() {
        data.file.clone()
    } else {
        data.title.clone()
    };
    Ok(fill(
        TEMPLATE,
        &[
            ("TITLE", html_escape(&title)),
            ("CSS", style_text(VIEWER_CSS)),
            ("DATA", json),
            ("THREE", script_text(THREE_JS)),
            ("ORBIT", script_text(ORBIT_JS)),
            (
                "VIEWER",
                script_text(&format!("{VIEWER_JS}\n{}", super::simulate::SIMULATE_JS)),
            ),
            ("THREE_VERSION", html_escape(THREE_VERSION)),
            ("THREE_LICENSE", html_escape(THREE_LICENSE)),
        ],
    ))
}

/// Array lengths of the data against its node and element counts (the page indexes them).
pub(super) fn check_data(d: &ViewData) -> Result<(), ViewError> {
    let (n, ne) = (d.nodes.len(), d.elements.len());
    let bad = |what: String| Err(ViewError::Data(what));
    for (k, f) in d.frames.iter().enumerate() {
        if f.x.len() != 3 * n || f.q.len() != 4 * n {
            return bad(format!(
                "frame {k} has {} positions for {n} nodes",
                f.x.len()
            ));
        }
    }
    for (k, a) in d.animations.iter().enumerate() {
        if a.u.len() != 3 * n || a.w.len() != 3 * n || a.frame >= d.frames.len() {
            return bad(format!("animation {k} does not fit the model"));
        }
    }
    for f in &d.fields {
        let sets = match f.per {
            FieldPer::Model => 1,
            FieldPer::Frame => d.frames.len(),
            FieldPer::Animation => d.animations.len(),
        };
        if f.values.len() != sets || f.values.iter().any(|v| v.len() != ne) {
            return bad(format!("field {} does not fit the model", f.key));
        }
    }
    for (k, e) in d.elements.iter().enumerate() {
        if e.nodes.iter().any(|&i| i >= n) {
            return bad(format!("element {k} names a node that does not exist"));
        }
    }
    Ok(())
}

/// Replace every `{{NAME}}` of the template in one pass (an inserted text is never scanned
/// again, so data that happens to contain `{{…}}` stays as it is).
pub(super) fn fill(template: &str, values: &[(&str, String)]) -> String {
    let mut out =
        String::with_capacity(template.len() + values.iter().map(|v| v.1.len()).sum::<usize>());
    let mut rest = template;
    while let Some(start) = rest.find("{{") {
        out.push_str(&rest[..start]);
        let after = &rest[start + 2..];
        match after.find("}}").and_then(|end| {
            let name = &after[..end];
            values
                .iter()
                .find(|(k, _)| *k == name)
                .map(|(_, v)| (v, end))
        }) {
            Some((v, end)) => {
                out.push_str(v);
                rest = &after[end + 2..];
            }
            None => {
                out.push_str("{{");
                rest = after;
            }
        }
    }
    out.push_str(rest);
    out
}

/// JSON inside a `<script>` element: `<`, `>` and `&` as `\u` escapes (valid JSON, and the
/// HTML parser can never see `</script>` or `<!--` in it).
pub fn script_json(json: &str) -> String {
    let mut s = String::with_capacity(json.len());
    for c in json.chars() {
        match c {
            '<' => s.push_str("\\u003c"),
            '>' => s.push_str("\\u003e"),
            '&' => s.push_str("\\u0026"),
            '\u{2028}' => s.push_str("\\u2028"),
            '\u{2029}' => s.push_str("\\u2029"),
            c => s.push(c),
        }
    }
    s
}

/// JavaScript source inside a `<script>` element: `</script` (any case) becomes `<\/script`,
/// which means the same in a JavaScript string, template or regular expression.
pub fn script_text(js: &str) -> String {
    let lower = js.to_ascii_lowercase();
    let mut out = String::with_capacity(js.len());
    let mut last = 0;
    for (i, _) in lower.match_indices("</script") {
        out.push_str(&js[last..i]);
        out.push_str("<\\/");
        last = i + 2;
    }
    out.push_str(&js[last..]);
    out
}

/// CSS inside a `<style>` element (no `</style` in it).
pub(super) fn style_text(css: &str) -> String {
    css.replace("</", "<\\/")
}

/// Text for HTML element content.
pub fn html_escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}
