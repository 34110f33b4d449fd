//! The library's errors are typed: each kind of bad input ends in its own variant, with the
//! fields a front end needs (the parameter's name, the names allowed, the motion, the pose, the
//! file) and a message a person can act on. One test per variant, driven through the public API.

mod common;

use common::{bottom, stone};
use rocking_stones::analysis::check_nu;
use rocking_stones::dynamics::drops::montecarlo::merge;
use rocking_stones::dynamics::pushes::Family;
use rocking_stones::dynamics::shaking::{place, rock_params, Pose};
use rocking_stones::dynamics::surface::Surface;
use rocking_stones::generate;
use rocking_stones::ground_motion::fragility::{FragilitySurface, Run};
use rocking_stones::ground_motion::read::AccelUnit;
use rocking_stones::ground_motion::Record;
use rocking_stones::study::mesh_files;
use rocking_stones::Error;

#[test]
fn a_value_out_of_range_names_its_parameter() {
    let e = check_nu(2.0).unwrap_err();
    match &e {
        Error::Parameter { name, value, expected } => {
            assert_eq!((name.as_str(), value.as_str(), expected.as_str()), ("nu", "2", "in (0, 1]"))
        }
        other => panic!("expected a parameter error, got {other:?}"),
    }
    assert_eq!(e.kind(), "parameter");
    // A front end spells the name its own way.
    assert_eq!(e.spelled(&|n| format!("--{n}")), "--nu must be in (0, 1], got 2");
    assert!(check_nu(0.5).is_ok());
}

#[test]
fn an_unknown_name_lists_the_names_known() {
    let e = "kick".parse::<Family>().unwrap_err();
    assert!(
        matches!(&e, Error::Unknown { what: "perturbation family", given, allowed } if given == "kick" && allowed == &["push", "spin"]),
        "{e:?}"
    );
    assert_eq!(e.to_string(), "unknown perturbation family \"kick\": expected one of push, spin");
    assert_eq!(e.kind(), "unknown-name");
    let e = "m/s3".parse::<AccelUnit>().unwrap_err();
    assert!(matches!(&e, Error::Unknown { what: "acceleration unit", allowed, .. } if allowed.len() == 3), "{e:?}");
    assert!("gal".parse::<AccelUnit>().is_ok());
}

#[test]
fn a_motion_that_cannot_drive_a_run_is_named() {
    let e = Record::new("quake.csv", 0.01, vec![[0.0; 3]]).unwrap_err();
    assert!(matches!(&e, Error::Motion { name, what } if name == "quake.csv" && what.contains("two samples")), "{e:?}");
    assert_eq!(e.to_string(), "quake.csv: a record needs at least two samples, got 1");
    let e = Record::new("quake.csv", 0.01, vec![[0.0; 3], [f64::NAN, 0.0, 0.0]]).unwrap_err();
    assert!(e.to_string().contains("sample 2 (t = 0.01 s) is not a finite number"), "{e}");
    assert_eq!(e.kind(), "motion");
    assert!(Record::new("quake.csv", 0.01, vec![[0.0; 3]; 2]).is_ok());
}

#[test]
fn a_pose_the_stone_cannot_stand_in_is_refused_with_the_ones_it_can() {
    let s = stone(generate::cuboid(1.0, 0.8, 0.6));
    let p = rock_params(Surface::RockOnConcrete, 0.5).unwrap();
    let e = place(&s, &Pose::Equilibrium { id: 999 }, &p).err().expect("facet 999 accepted");
    match &e {
        Error::Pose { pose, what } => {
            assert_eq!(pose, "equilibrium:999");
            assert!(what.contains("stable ones (with their hull facets):"), "{what}");
            assert!(what.contains(&bottom(&s).to_string()), "{what}");
        }
        other => panic!("expected a pose error, got {other:?}"),
    }
    assert_eq!(e.kind(), "pose");
    assert!(place(&s, &Pose::Equilibrium { id: bottom(&s) }, &p).is_ok());
}

#[test]
fn results_that_do_not_belong_together_are_a_checkpoint_error() {
    let e = merge(&[]).unwrap_err();
    assert!(matches!(&e, Error::Checkpoint(m) if m.contains("nothing to merge")), "{e:?}");
    assert_eq!(e.kind(), "checkpoint");
}

#[test]
fn a_model_that_cannot_be_fitted_says_why() {
    let run = |pga_g: f64, overturned: bool| Run { pga_g, pgv_over_pga_s: 0.1, overturned };
    let e = FragilitySurface::fit(&[run(0.1, false), run(0.2, true)]).unwrap_err();
    assert!(matches!(&e, Error::Fit(m) if m.contains("at least three runs, got 2")), "{e:?}");
    let e = FragilitySurface::fit(&[run(0.1, false), run(0.2, false), run(0.3, false)]).unwrap_err();
    assert!(e.to_string().starts_with("cannot fit a fragility surface: all 3 runs left the rock standing"), "{e}");
    assert_eq!(e.kind(), "fit");
}

#[test]
fn a_study_folder_without_scans_is_named() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("notes.txt"), "no scans here").unwrap();
    let e = mesh_files(dir.path()).unwrap_err();
    assert!(matches!(&e, Error::Study { path, .. } if path == dir.path()), "{e:?}");
    assert!(e.to_string().ends_with("no .stl, .obj or .ply files in this folder"), "{e}");
    assert_eq!(e.kind(), "study");
    // The folder stays named when a caller attaches a path.
    assert!(e.with_path("other").to_string().starts_with(&dir.path().display().to_string()));
}
