//! The HTML page around the report's sections: styles and the script that
//! zooms and pans the path views (wheel to zoom about the pointer, drag to
//! pan, double-click to reset), all inline.

use super::chart::esc;

const STYLE: &str = r#"
body { font: 14px/1.4 system-ui, sans-serif; margin: 24px; color: #222; max-width: 1000px; }
h1 { font-size: 22px; margin-bottom: 0; }
.sub { color: #666; margin-top: 4px; }
h2 { font-size: 17px; margin-top: 28px; border-bottom: 1px solid #ddd; }
h3 { font-size: 14px; margin: 12px 0 4px; }
table { border-collapse: collapse; font-size: 13px; }
th, td { border: 1px solid #ddd; padding: 3px 8px; text-align: right; }
th:first-child, td:first-child { text-align: left; }
tr.failed td { color: #b00; }
svg.pathview { width: 100%; height: 560px; border: 1px solid #ccc; background: #fff; cursor: grab; }
svg.pathview polyline { fill: none; vector-effect: non-scaling-stroke; stroke-linejoin: round; }
svg.pathview polyline.band { vector-effect: none; stroke-linecap: round; stroke-opacity: 0.45; }
svg.pathview polyline.original { stroke-width: 1.2; }
svg.pathview polyline.written { stroke-width: 1.5; }
svg.pathview polyline.rapid { stroke-width: 1; stroke-dasharray: 4 4; }
svg.pathview circle.marker { fill-opacity: 0.8; }
.legend span { margin-right: 14px; font-size: 12px; white-space: nowrap; }
.legend i { display: inline-block; width: 18px; height: 0; border-top: 3px solid; margin-right: 4px; vertical-align: middle; }
.legend i.band { border-top-width: 8px; opacity: 0.5; }
.legend i.rapid { border-top-style: dashed; }
.legend i.dot { width: 8px; height: 8px; border: 0; border-radius: 4px; }
svg.chart { width: 100%; height: auto; margin: 6px 0 14px; }
svg.chart polyline { fill: none; stroke-width: 1.3; }
svg.chart .dashed { stroke-dasharray: 5 3; }
svg.chart line.key { stroke-width: 3; }
svg.chart .grid { stroke: #eee; }
svg.chart .frame { fill: none; stroke: #999; }
svg.chart .tick { font-size: 11px; fill: #555; }
svg.chart .axis { font-size: 12px; fill: #333; }
svg.chart .title { font-size: 13px; font-weight: 600; fill: #222; }
.hint { color: #777; font-size: 12px; }
#errors { color: #b00; }
"#;

/// Zoom and pan of every `svg.pathview`; markers keep their size on screen.
/// Script errors are written into `#errors` (a page that loads cleanly has
/// it empty), and `body[data-ready]` says the script ran.
const SCRIPT: &str = r#"
window.onerror = function (msg) {
  document.getElementById('errors').textContent += msg + '\n';
};
(function () {
  function box(svg) { return svg.getAttribute('viewBox').split(' ').map(Number); }
  function set(svg, b) {
    svg.setAttribute('viewBox', b.join(' '));
    var r = Math.max(b[2], b[3]) / 300;
    svg.querySelectorAll('circle.marker').forEach(function (c) { c.setAttribute('r', r); });
  }
  function point(svg, e) {
    var b = box(svg), rect = svg.getBoundingClientRect();
    var s = Math.max(b[2] / rect.width, b[3] / rect.height);
    var ox = b[0] + b[2] / 2 - s * rect.width / 2, oy = b[1] + b[3] / 2 - s * rect.height / 2;
    return [ox + (e.clientX - rect.left) * s, oy + (e.clientY - rect.top) * s, s];
  }
  document.querySelectorAll('svg.pathview').forEach(function (svg) {
    var home = box(svg), drag = null;
    svg.addEventListener('wheel', function (e) {
      e.preventDefault();
      var p = point(svg, e), b = box(svg), f = Math.exp(e.deltaY * 0.0015);
      set(svg, [p[0] - (p[0] - b[0]) * f, p[1] - (p[1] - b[1]) * f, b[2] * f, b[3] * f]);
    }, { passive: false });
    svg.addEventListener('mousedown', function (e) { drag = [e.clientX, e.clientY]; });
    window.addEventListener('mouseup', function () { drag = null; });
    svg.addEventListener('mousemove', function (e) {
      if (!drag) return;
      var b = box(svg), s = point(svg, e)[2];
      set(svg, [b[0] - (e.clientX - drag[0]) * s, b[1] - (e.clientY - drag[1]) * s, b[2], b[3]]);
      drag = [e.clientX, e.clientY];
    });
    svg.addEventListener('dblclick', function () { set(svg, home.slice()); });
  });
  document.body.setAttribute('data-ready', '1');
})();
"#;

/// The page: a title, a subtitle and `(heading, html)` sections.
pub fn page(title: &str, subtitle: &str, sections: &[(&str, String)]) -> String {
    let mut o = String::from("<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">");
    o.push_str(&format!(
        "<title>fairpath report: {}</title><style>{STYLE}</style></head><body>",
        esc(title)
    ));
    o.push_str(&format!(
        "<h1>fairpath report: {}</h1><p class=\"sub\">{}</p><pre id=\"errors\"></pre>",
        esc(title),
        esc(subtitle)
    ));
    for (heading, html) in sections {
        o.push_str(&format!("<h2>{}</h2>", esc(heading)));
        if heading.starts_with("Path") {
            o.push_str(
                "<p class=\"hint\">Wheel: zoom about the pointer; drag: pan; \
                 double-click: back to the whole path.</p>",
            );
        }
        o.push_str(html);
    }
    o.push_str(&format!("<script>{SCRIPT}</script></body></html>\n"));
    o
}
