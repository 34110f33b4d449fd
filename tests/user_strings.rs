//! What a person reads: every enum value the CLI prints has a user-facing name (no
//! Rust `Debug` form), the summaries use correct plurals and units, `planar` and `analyze` read
//! the macro scale by the same rule (an unclear plateau falls back to the paper's ν = 0.0035),
//! and `report.html` is one self-contained file.

use rocking_stones::analysis::PAPER_NU;
use rocking_stones::dynamics::certificate::CertificateMode;
use rocking_stones::dynamics::drops::params::{Preset, SpinDistribution};
use rocking_stones::dynamics::pushes::Family;
use rocking_stones::dynamics::resting::outcome::Outcome;
use rocking_stones::dynamics::stone::Class;
use rocking_stones::dynamics::surface::Surface;
use rocking_stones::equilibria::Kind;
use rocking_stones::hierarchy::NuSource;
use rocking_stones::planar::{ellipse_polygon, sides_for_k, PlanarAnalysis, Sampling, DEFAULT_DEGENERACY_TOL};
use rocking_stones::report::names::{plural, Unit};
use rocking_stones::shape::Zingg;
use std::process::Command;

/// Internal names that must never reach a person: Debug braces and options, CamelCase
/// identifiers (a lower-case letter followed by an upper-case one inside a word).
fn internal(text: &str) -> Option<String> {
    for bad in ["{", "}", "(None)", "Some(", "None)", "PaperDefault", "ArcLength", "UnclearPlateau"] {
        if text.contains(bad) {
            return Some(bad.to_string());
        }
    }
    let chars: Vec<char> = text.chars().collect();
    for w in chars.windows(2) {
        if w[0].is_ascii_lowercase() && w[1].is_ascii_uppercase() {
            return Some(format!("CamelCase at \"{}{}\"", w[0], w[1]));
        }
    }
    None
}

fn assert_readable(what: &str, text: &str) {
    assert!(!text.trim().is_empty(), "{what}: empty");
    if let Some(bad) = internal(text) {
        panic!("{what}: internal name ({bad}) in:\n{text}");
    }
}

#[test]
fn the_checker_catches_debug_names() {
    assert!(internal(&format!("{:?}", Sampling::Random { seed: 1 })).is_some());
    assert!(internal(&format!("{:?}", Sampling::ArcLength)).is_some());
    assert!(internal(&format!("{:?}", NuSource::PaperDefault)).is_some());
    assert!(internal(&format!("({:?})", None::<u32>)).is_some());
    assert!(internal("1 rocking equilibrium, 3 drops").is_none());
}

#[test]
fn every_enum_value_has_a_user_facing_name() {
    let mut names: Vec<(String, String)> = Vec::new();
    let mut add = |what: &str, shown: String| names.push((what.to_string(), shown));
    for k in Kind::ALL {
        add("Kind", k.to_string());
        add("Kind letter", k.letter().to_string());
        add("Kind site", k.site_name().to_string());
    }
    for s in NuSource::ALL {
        add("NuSource", s.to_string());
    }
    for s in [Sampling::ArcLength, Sampling::Angle, Sampling::Random { seed: 1 }] {
        add("Sampling", s.to_string());
    }
    for c in Class::ALL {
        add("Class", c.to_string());
    }
    for f in Family::ALL {
        add("Family", f.to_string());
    }
    for o in Outcome::ALL {
        add("Outcome", o.to_string());
    }
    for c in [CertificateMode::None, CertificateMode::Facet, CertificateMode::Flock] {
        add("CertificateMode", c.to_string());
    }
    for s in SpinDistribution::ALL {
        add("SpinDistribution", s.to_string());
    }
    for p in Preset::ALL {
        add("Preset", p.to_string());
    }
    for s in Surface::ALL {
        add("Surface", s.to_string());
    }
    for z in [Zingg::Disc, Zingg::Spheroid, Zingg::Blade, Zingg::Rod] {
        add("Zingg", z.to_string());
    }
    assert_eq!(names.len(), 9 + 3 + 3 + 2 + 2 + 3 + 3 + 2 + 3 + 4 + 4);
    for (what, shown) in &names {
        assert_readable(what, shown);
    }
    // what the summaries print, in words
    assert_eq!(Sampling::Random { seed: 7 }.to_string(), "random arc-length positions, seed 7");
    assert_eq!(NuSource::PaperDefault.to_string(), "no clear plateau: the paper's hand experimenter");
    assert_eq!(Kind::Saddle.letter(), "H");
}

#[test]
fn plurals_and_units() {
    assert_eq!(plural(1u64, "rocking equilibrium", "rocking equilibria"), "1 rocking equilibrium");
    assert_eq!(plural(11u64, "rocking equilibrium", "rocking equilibria"), "11 rocking equilibria");
    assert_eq!(plural(0u64, "drop", "drops"), "0 drops");
    assert_eq!(Unit::named("mm").volume(), "mm³");
    assert_eq!(Unit::named(" ").length(), "mesh units");
}

/// planar and analyze share one macro-scale rule: an unclear plateau is not a macro scale, the
/// paper's ν = 0.0035 is used instead (README, `hierarchy::macro_nu`).
#[test]
fn planar_uses_the_same_unclear_plateau_rule_as_analyze() {
    // an ellipse 1 : 1.2 cut at random: its longest step is not clear
    let p = ellipse_polygon(1.2, sides_for_k(20), Sampling::Random { seed: 1 }).unwrap();
    let a = PlanarAnalysis::new(p, DEFAULT_DEGENERACY_TOL).unwrap();
    let r = a.report(None);
    let plateau = r.plateau.expect("a plateau");
    assert!(!plateau.clear, "the test needs an unclear plateau: {plateau:?}");
    assert_eq!((r.nu, r.nu_source), (PAPER_NU, NuSource::PaperDefault));
    assert_eq!((r.nu, r.nu_source), rocking_stones::hierarchy::macro_nu(None, Some(plateau)));
    // and its own ν would give other counts: the rule matters here
    let own = a.report(Some((plateau.nu_lo * plateau.nu_hi).sqrt()));
    assert_ne!(own.macro_counts, r.macro_counts);
}

/// Run the CLI; its outputs with the temporary folder's (random) name replaced by `TMP`.
fn rocking(args: &[&str]) -> (bool, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_rocking")).args(args).output().expect("run rocking");
    let tmp = std::env::temp_dir();
    let clean = |b: &[u8]| {
        let text = String::from_utf8_lossy(b).into_owned();
        // /tmp/.tmpAbC123/cube.stl → TMP/cube.stl
        let re_start = tmp.to_string_lossy().into_owned();
        let mut out = String::new();
        let mut rest = text.as_str();
        while let Some(i) = rest.find(&re_start) {
            out.push_str(&rest[..i]);
            out.push_str("TMP");
            let tail = &rest[i + re_start.len()..];
            let tail = tail.trim_start_matches('/');
            let skip = tail.find('/').unwrap_or(0);
            rest = &tail[skip..];
        }
        out.push_str(rest);
        out
    };
    (out.status.success(), clean(&out.stdout), clean(&out.stderr))
}

#[test]
fn cli_summaries_use_user_facing_names() {
    let dir = tempfile::tempdir().unwrap();
    let cube = dir.path().join("cube.stl");
    let cube = cube.to_str().unwrap();
    assert!(rocking(&["generate", "cube", "-o", cube]).0);
    for sampling in ["arclength", "angle", "random"] {
        let (ok, out, err) = rocking(&["planar", "ellipse", "--a", "1.2", "--k", "20", "--sampling", sampling]);
        assert!(ok, "{err}");
        assert_readable(&format!("planar --sampling {sampling}"), &out);
        if sampling == "random" {
            assert!(out.contains("macro scale ν = 0.0035 (no clear plateau"), "{out}");
        }
    }
    let (ok, out, err) = rocking(&["planar", "regular", "-n", "6"]);
    assert!(ok, "{err}");
    assert_readable("planar regular", &out);
    assert!(out.contains("0 rocking equilibria"), "{out}");
    let (ok, _, err) = rocking(&["planar", "regular", "-n", "2"]);
    assert!(!ok && err.contains("at least 3") && !err.contains("<memory>"), "{err}");

    let (ok, out, err) = rocking(&["analyze", cube, "--unit", "cm"]);
    assert!(ok, "{err}");
    assert_readable("analyze", &out);
    let solid = out.lines().find(|l| l.trim_start().starts_with("solid")).unwrap();
    assert!(solid.contains(" cm³, area ") && solid.contains(" cm², G = (") && solid.ends_with(") cm"), "{solid}");
    assert!(!solid.contains("e-") && !solid.contains("e+") && !solid.contains("e0"), "plain decimals: {solid}");
    assert!(!out.contains("inf") && !out.contains("NaN"), "{out}");
    assert!(out.contains("macro    ν = 0.0035 (no clear plateau"), "{out}");
    let (_, out, _) = rocking(&["analyze", cube]);
    assert!(out.contains("mesh units³"), "{out}");

    for cert in ["none", "facet", "flock"] {
        let (ok, out, err) = rocking(&["drop", cube, "--size", "0.01", "-n", "1", "--certificate", cert]);
        assert!(ok, "{err}");
        assert_readable(&format!("drop --certificate {cert}"), &out);
        assert!(out.contains("1 of 1 drop "), "{out}");
    }
    let (ok, _, err) = rocking(&["study", dir.path().join("nonexist").to_str().unwrap()]);
    assert!(!ok && err.contains("does not exist"), "{err}");
    let (ok, _, err) = rocking(&["study", cube]);
    assert!(!ok && err.contains("not a folder"), "{err}");
    let (_, help, _) = rocking(&["drop", "--help"]);
    assert!(help.contains("drops.json") && !help.contains("report.json"), "{help}");
}

/// `analyze -o` writes one self-contained report.html: plots inline, the hull data inline, no
/// address to fetch.
#[test]
fn report_html_is_self_contained() {
    let dir = tempfile::tempdir().unwrap();
    let (ok, _, err) = rocking(&["analyze", "--unit", "mm", "-o", dir.path().to_str().unwrap()]);
    assert!(ok, "{err}");
    let html = std::fs::read_to_string(dir.path().join("report.html")).unwrap();
    assert_eq!(html.matches("src=\"data:image/png;base64,").count(), 2, "n_nu.png and hull.png inline");
    for remote in ["http://", "https://", "src=\"//", "<link", "@import"] {
        assert!(!html.contains(remote), "report.html refers to {remote}");
    }
    // the hull data: 1158 facets of the bundled stone, 15 + 13 + 26 micro-equilibria
    let start = html.find("var HULL = ").unwrap() + "var HULL = ".len();
    let end = start + html[start..].find(";\n</script>").unwrap();
    let hull: serde_json::Value = serde_json::from_str(&html[start..end]).unwrap();
    assert_eq!(hull["facets"].as_array().unwrap().len(), 1158);
    assert_eq!(hull["equilibria"].as_array().unwrap().len(), 15 + 13 + 26);
    assert_eq!(hull["unit"], "mm");
    assert!(hull["arcs"].as_array().unwrap().iter().all(|s| !s["on"].as_array().unwrap().is_empty()));
    assert!(!html.contains("{{"), "a template slot was left unfilled");
}
