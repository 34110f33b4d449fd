//! Figure 4 of the paper: a grid of arc-length discretised ellipses, rows k (N = 4k − 2),
//! columns the axis ratio a, each with its micro-equilibria marked and S written.
//!
//! Run: `cargo experiment fig4_ellipse_grid` → `results/planar/` (fig4_grid.csv,
//! fig4_grid.png, fig4.md); the README's prose is `experiments/readme/fig4_ellipse_grid.md`.

use rocking_stones::hierarchy::Kind;
use rocking_stones::planar::{sides_for_k, table1, PlanarAnalysis, Sampling};
use rocking_stones::prelude::*;

use experiments::harness;
use harness::{Context, Result, Results};

const KS: [usize; 4] = [3, 6, 12, 50];
const AS: [f64; 5] = [1.05, 1.1, 1.2, 1.5, 2.0];

fn main() -> Result<()> {
    let common = harness::common_args("The grid of discretised ellipses.");
    let out = Results::open("planar", &common)?;
    let limit = |a: f64| table1(a).map(|t| t.total_stable).context("no limit for this a");
    let bare = |lo, hi| Axis::linear("", lo, hi).ticks(0).no_grid().space(0);
    let (mut csv, mut panels, mut rows) = (Vec::new(), Vec::new(), Vec::new());
    for k in KS {
        let n = sides_for_k(k);
        let mut row = Vec::new();
        for a in AS {
            let an = PlanarAnalysis::of_ellipse(a, n, Sampling::ArcLength)?;
            let r = an.report(None);
            let (s, u, (ms, mu)) = (r.stable, r.unstable, (r.macro_counts.stable, r.macro_counts.unstable));
            let t = |v: usize| v.to_string();
            csv.push([t(k), t(n), a.to_string(), t(s), t(u), t(ms), t(mu), t(limit(a)?)]);
            row.push(s);
            let outline = an.polygon.closed_outline();
            let chart = Chart::new(bare(-2.2, 2.2), bare(-1.3, 1.3))
                .title(format!("k = {k} (N = {n}), a = {a}: S = {s}"))
                .line_width(&outline, RGBColor(0, 0, 0), 1);
            // One layer per point, in order along the outline, so that neither kind hides the other.
            panels.push(an.equilibria.points.iter().fold(chart, |c, p| {
                let colour = if p.kind == Kind::Stable { colors::VERMILLION } else { colors::BLUE };
                c.dots(&[(p.point.x, p.point.y)], colour)
            }));
        }
        rows.push(serde_json::json!({ "k": k, "s": row }));
    }
    out.csv("fig4_grid.csv", &["k", "sides", "a", "S", "U", "macro_S", "macro_U", "limit_S_8m+2"], csv)?;
    let title =
        "Arc-length discretised ellipses: rows k (N = 4k − 2), columns a; dots: vermillion = stable, blue = unstable";
    Figure::new(title, AS.len(), panels).save(&out.path("fig4_grid.png"), (1720, 1010))?;
    let limits = AS.iter().map(|&a| limit(a)).collect::<Result<Vec<_>>>()?;
    let as_ = AS.map(|a| a.to_string());
    out.page(
        "fig4.md",
        include_str!("readme/fig4_ellipse_grid.md"),
        serde_json::json!({ "as": as_, "rows": rows, "limits": limits }),
    )
}
