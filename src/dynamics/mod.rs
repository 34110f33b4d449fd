//! Rigid-body dynamics of a stone on the ground (rapier3d); `docs/methods.md` describes the
//! methods. The folders are the stages a run passes through, lowest first:
//!
//! ```text
//!                 size ──────────────┐            (the stone's real size: given, known, assumed)
//!                                    ▼
//! engine ──▶ stone ──▶ certificate ──▶ drops      (launch ▶ one drop / batches ▶ Monte Carlo runs)
//!   │          │                  └──▶ pushes     (kick ▶ trial ▶ robustness)
//!   │          └──▶ resting ─────────▶ pushes
//!   └─▶ surface ─▶ resting ──────────▶ shaking    (drive ▶ sweep / field rock ▶ records ▶ ensemble)
//! ```
//!
//! * [`engine`] — what every run is made of: the rapier world, the one contact law, free flight,
//!   impact sub-steps, the run loop and its rest rules, and the parameters they take.
//! * [`stone`] — the one prepared stone (body, merge tree, facet → equilibrium → flock) and the
//!   one rule for where a stone came to rest.
//! * [`surface`] — named surface pairs: friction, restitution, rolling-resistance length.
//! * [`size`] — the real size of a stone: given, known (the bundled stone) or assumed.
//! * [`certificate`] — the energy certificate that ends a run once its outcome is certain.
//! * [`drops`] — drops and throws: one, a batch in one world, or many in parallel.
//! * [`resting`] — a stone put at rest on a stable micro-equilibrium: the start of every push
//!   and shaking run, its contact, and how such a run ends.
//! * [`pushes`] — pushes and spins of a resting stone, and its robustness.
//! * [`shaking`] — the ground shaken under a resting stone: fragility sweeps, field rocks,
//!   batches of records, ensembles, and Housner's rigid block as a reference.

pub mod certificate;
pub mod drops;
pub mod engine;
pub mod pushes;
pub mod resting;
pub mod shaking;
pub mod size;
pub mod stone;
pub mod surface;
