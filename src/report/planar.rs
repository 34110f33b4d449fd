//! What a person reads of a planar analysis ([`crate::planar`]): the summary of `rocking planar`.

use super::names::{number, plural};
use crate::planar::{PlanarReport, Sampling, Table1};
use serde::Serialize;

/// The polygon a planar analysis ran on, as the summary and the JSON output name it.
#[derive(Clone, Copy, Debug, Serialize)]
#[serde(tag = "kind", rename_all = "lowercase")]
pub enum ShapeInfo {
    /// A polygon inscribed in the ellipse with semi-axes `a` and 1.
    Ellipse {
        /// Semi-axis along x (the other is 1).
        a: f64,
        /// The paper's k when the sides were given as N = 4k − 2.
        k: Option<usize>,
        /// Number of sides N.
        sides: usize,
        /// How the ellipse was discretised.
        sampling: Sampling,
    },
    /// A regular polygon.
    Regular {
        /// Number of sides.
        n: usize,
    },
}

/// A readable summary of a planar analysis of `info` (with Table 1's k → ∞ `limit` for an ellipse).
pub fn summary(info: &ShapeInfo, r: &PlanarReport, limit: Option<&Table1>) -> String {
    use std::fmt::Write;
    let mut s = String::new();
    match info {
        ShapeInfo::Ellipse { a, sides, sampling, .. } => {
            let _ = writeln!(s, "ellipse 1 : {a} (major axis x), {sides} sides, sampling: {sampling}");
        }
        ShapeInfo::Regular { n } => {
            let _ = writeln!(s, "regular {n}-gon");
        }
    }
    let _ = writeln!(
        s,
        "micro-equilibria: S = {}, U = {}   (R_min = {:.6}, R_max = {:.6}, v_max = {:.4}, degenerate decisions: {})",
        r.stable, r.unstable, r.r_min, r.r_max, r.v_max, r.degenerate_decisions
    );
    match &r.plateau {
        Some(p) => {
            let _ = writeln!(
                s,
                "plateau: ν ∈ [{}, {}], {} decades, clarity {}, {} → S = {}, U = {}",
                number(p.nu_lo, 4),
                number(p.nu_hi, 4),
                fmt_inf(p.decades),
                fmt_inf(p.clarity),
                if p.clear { "clear" } else { "NOT clear" },
                p.counts.stable,
                p.counts.unstable
            );
        }
        None => {
            let _ = writeln!(s, "plateau: none (nothing to cancel)");
        }
    }
    let _ = writeln!(
        s,
        "macro scale ν = {} ({}): S = {}, U = {}",
        number(r.nu, 5),
        r.nu_source,
        r.macro_counts.stable,
        r.macro_counts.unstable
    );
    for f in &r.flocks {
        let kind = f.kind.name();
        let _ = writeln!(
            s,
            "  flock {:>3} {:<8} root {:>5}: {} stable + {} unstable",
            f.id, kind, f.root, f.stable, f.unstable
        );
    }
    let _ = writeln!(
        s,
        "{} (stable sides in unstable flocks)",
        plural(r.rocking.len() as u64, "rocking equilibrium", "rocking equilibria")
    );
    for x in r.rocking.iter().take(20) {
        let _ = writeln!(s, "  side {:>5}  φ = {:+.4}  R = {:.6}  flock {}", x.side, x.phi, x.r, x.flock);
    }
    if let Some(t) = limit {
        let _ = writeln!(
            s,
            "Table 1 (k → ∞): stable flocks {} + {}, unstable flocks {} + {}, total S = {}{}",
            t.stable_flock.0,
            t.stable_flock.1,
            t.unstable_flock.0,
            t.unstable_flock.1,
            t.total_stable,
            if t.on_jump { " (a²/(2(a²−1)) is an integer: the limit sits on a jump)" } else { "" }
        );
    }
    s
}

fn fmt_inf(x: f64) -> String {
    if x.is_finite() {
        format!("{x:.2}")
    } else {
        "∞".into()
    }
}
