//! Toppling under ground shaking: a stone standing on the ground, the ground driven
//! under it by a recorded or synthetic motion.
//!
//! * [`drive`] — the one ground drive: a [`crate::ground_motion::Record`] (real time, SI, up to
//!   three components) under a stone of real size, by the Froude-exact scaled run, and the shaken
//!   run every mode makes ([`drive::shake_placed`]).
//! * [`sweep`] — fragility curves of the stable micro-equilibria: the motion scaled to each PGA of
//!   a grid, random azimuths, P(toppled) with intervals and PGA₅₀.
//! * [`rock`] — a field rock in a physical pose (as scanned, on a facet, or a quaternion) under one
//!   record at one scale.
//! * [`records`] — records × scale factors on a field rock (with or without an ensemble) and the
//!   fragility surface P(overturn | PGA, PGV/PGA) fitted to them.
//! * [`ensemble`] — the same rock over what is not known about it (base contact, azimuth, sign,
//!   contact): P(overturn) with its interval and the inputs it is most sensitive to.
//! * [`housner`] — Housner's rigid block, the reference they are checked against.
//!
//! Sweeps and field rocks run on the contact of every resting run ([`crate::dynamics::resting`]: the surface
//! pair at the stone's real size), rest by positions over windows
//! ([`crate::dynamics::engine::rest::PositionRest`]) and classify the outcome by the quasi-static descent.

pub mod drive;
pub mod ensemble;
pub mod housner;
pub mod journal;
pub mod records;
pub mod rock;
pub mod sweep;

pub use drive::{shake_placed, GroundDrive, Placed, Shaken};
pub use ensemble::{
    field_members, member_rocks, run_ensemble, BaseUncertainty, Ensemble, EnsembleSpec, FieldRock, HiddenBase, Member,
    MemberRock, Uncertainty,
};
pub use records::{run_batch, run_record, RecordRun, ShakeBatch};
pub use rock::{default_poses, driven, place, rock_params, shake_record, stone_of, Pose, RockRun, RockSetup};
pub use sweep::{
    default_pulse, default_starts, pga_grid, pgas_for, shake_stream, shake_trial, sine_pulse, sweep_fragility,
    sweep_fragility_monitored, Fragility, MotionInfo, ShakeConfig, ShakeReport, ShakeTrial,
};
