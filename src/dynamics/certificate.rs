//! The energy certificate: a run on a passive contact whose outcome (final facet or flock) is
//! already certain from its energy may end early (`docs/methods.md`).
//!
//! **Certificate: an argument whose one gap is measured, not a proof.** A rigid body on a passive
//! contact never gains mechanical energy, and z_G ≥ h(down) (the support function), so E/(m g)
//! bounds h(down) for the rest of the motion; when the sublevel component of h that holds the
//! current down direction contains a single stable facet (or a single flock) of the merge tree,
//! the outcome is decided ([`EnergyCertificate`]). The parts of the contact this project writes
//! only dissipate (the rolling resistance of [`crate::dynamics::engine::world`], and its impact law, which adds no
//! energy beyond what the step's start or rapier's own step had). Rapier's soft-constraint solver
//! is not proven to: what it may give back is covered by a margin ([`CERTIFICATE_MARGIN`]) whose
//! size is measured, not derived. The certificate is never asked while a ground motion drives the
//! stone (that system is not passive), nor while the soft contact is compressed
//! ([`CERTIFICATE_MAX_COMPRESSION`]). Above the merge tree's decision ceiling
//! ([`crate::basins::MergeTree::decision_ceiling`]) nothing can be decided and a check costs O(1);
//! below it, a check is a descent of h.
//!
//! **Measured limit.** With rapier's own flight (`--flight rapier`, impacts found after the stone
//! is already up to 0.2 R_max inside the ground), rapier's contact solver (4 iterations) does not
//! conserve energy in the hard first impact of a throw (≈ 10 m/s of the scaled body, 35 rad/s of
//! spin): L could rise by up to 1.8 R_max there (0.4 at 16 iterations, 0.08 at 64). The certificate can only decide once
//! L ≤ max h = R_max, where later impacts are slower than a drop from 1 R_max, and there no rise
//! beyond the margin is measured (`tests/contact.rs`); an early injection only delays the decision.
//! Certified outcomes equal full settling drop by drop on 400 throws (`tests/throws.rs`) and in
//! the `drop` and `throw` presets of `results/drops_certificate/` (3 bodies × 300 drops each).

use crate::dynamics::engine::run::{Certificate, Decided, NoCertificate, CERTIFICATE_EVERY};
use crate::dynamics::engine::world::BodyState;
use crate::dynamics::stone::Stone;
use serde::{Deserialize, Serialize};

/// How early the energy certificate ends a run.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum CertificateMode {
    /// Simulate every run until it rests (or the time cap).
    None,
    /// Stop once the final facet is certain.
    Facet,
    /// Stop once the final flock is certain.
    Flock,
}

impl CertificateMode {
    /// The user-facing name.
    pub fn name(self) -> &'static str {
        match self {
            CertificateMode::None => "none",
            CertificateMode::Facet => "facet",
            CertificateMode::Flock => "flock",
        }
    }
}

impl std::str::FromStr for CertificateMode {
    type Err = crate::Error;

    /// `none`, `facet` or `flock`: the same names for drops and pushes.
    fn from_str(s: &str) -> crate::Result<CertificateMode> {
        [CertificateMode::None, CertificateMode::Facet, CertificateMode::Flock]
            .into_iter()
            .find(|m| m.name() == s)
            .ok_or_else(|| crate::Error::unknown("certificate", s, &["none", "facet", "flock"]))
    }
}

/// Safety margin added to the energy level before asking the merge tree, in units of R_max: the
/// body sinks into the ground by the contact's compression (the certificate is asked only up to
/// [`CERTIFICATE_MAX_COMPRESSION`]), so h(down) can be above z_G, and hence above L, by that
/// much, plus what the solver gives back. **Measured, not proven** — the largest later rise of
/// h(down) above the L read at any state where the certificate may be asked is 1.46·10⁻³ R_max
/// over 72 000 drops at the default step (the bundled stone and 39 scanned meshes, 3 presets,
/// rapier's flight and free flight), so the margin is 2.1 times it, and 0 of 7 940 691 decisions
/// there (103 282 of them the first of their drop) name another facet or flock than full settling
/// reaches (`results/certificate_decisions/`). Without a margin the tree decides wrongly (11 of
/// 11 472 decisions in `results/certificate_margin/`, none from 3·10⁻⁴ on).
pub const CERTIFICATE_MARGIN: f64 = 3e-3;

/// The certificate is asked only while the contact is nearly relaxed: G at most this far (R_max)
/// below h(down), i.e. the contact compressed by at most 10⁻³ R_max. In a hard impact the contact
/// is compressed and L = z_G + KE/(m g) does not count what the compression will give back.
///
/// *What the compression can give back: not bounded by a formula.* Read as a linear spring of
/// rapier's natural frequency f, a compression c would store ½ (2π f)² c² / g per unit weight:
/// 7.2·10⁻³ R_max at f = 60 Hz and c = 10⁻³ R_max (2.9·10⁻² at the 120 Hz of runs that start at
/// rest) — more than the margin. Rapier's contact is not that spring: its soft constraint
/// (TGS-soft, rapier 0.36) pushes a penetration out with a bias velocity that the relaxation pass
/// of every sub-step takes away again, so a compression is restored mostly as height (which L
/// counts once the contact has relaxed). That is an argument about the solver, not a bound; what
/// is left is the solver's own error, and it is measured on the quantity the certificate needs:
/// over the whole future of every state where the certificate may be asked (relaxed,
/// L ≤ 1 R_max), how far the support height h(down) rises above the L read there
/// (`tests/contact.rs` on pebble throws; `results/certificate_decisions/` on 72 000 drops of 40
/// bodies, largest 1.46·10⁻³ R_max, under [`CERTIFICATE_MARGIN`]).
pub const CERTIFICATE_MAX_COMPRESSION: f64 = 1e-3;

/// The merge-tree energy certificate ([`crate::basins`], `docs/methods.md`) on a prepared stone,
/// at the facet or flock level.
pub struct EnergyCertificate<'a> {
    stone: &'a Stone,
    flock_level: bool,
    /// [`crate::basins::MergeTree::decision_ceiling`] (mesh units): at or above this energy
    /// level (with the margin) nothing can be decided, without a descent.
    ceiling: f64,
    /// Added to the energy level before asking the merge tree (R_max).
    margin: f64,
}

impl<'a> EnergyCertificate<'a> {
    /// The certificate of `mode` for `stone` (None for [`CertificateMode::None`]).
    pub fn new(stone: &'a Stone, mode: CertificateMode) -> Option<Self> {
        Self::with_margin(stone, mode, CERTIFICATE_MARGIN)
    }

    /// The certificate of `mode` with another `margin` (R_max) than [`CERTIFICATE_MARGIN`]: for
    /// measuring what the margin does (`experiments/certificate_margin.rs`), not for runs.
    pub fn with_margin(stone: &'a Stone, mode: CertificateMode, margin: f64) -> Option<Self> {
        match mode {
            CertificateMode::None => None,
            _ => {
                let flock_level = mode == CertificateMode::Flock;
                let ceiling = stone.tree.decision_ceiling(flock_level.then_some(&stone.facet_flock[..]));
                Some(EnergyCertificate { stone, flock_level, ceiling, margin })
            }
        }
    }

    /// Whether the contact is relaxed enough for L to bound the energy
    /// ([`CERTIFICATE_MAX_COMPRESSION`]). h(down) by hill climbing (O(1) in the hull size, exact
    /// to the collider's f32 rounding, 10⁻⁷ R_max: [`crate::dynamics::engine::body::Body::support_climb`]).
    pub fn relaxed(&self, s: &BodyState) -> bool {
        self.stone.body.support_climb(&s.down) - s.z <= CERTIFICATE_MAX_COMPRESSION
    }

    /// The stable facet that is certain in state `s`, if any.
    pub fn facet(&self, s: &BodyState) -> Option<u32> {
        if !self.relaxed(s) {
            return None;
        }
        self.stone.tree.decided(&s.down, (s.level + self.margin) * self.stone.body.r_max)
    }

    /// The flock that is certain in state `s`, if any.
    pub fn flock(&self, s: &BodyState) -> Option<usize> {
        if !self.relaxed(s) {
            return None;
        }
        let level = (s.level + self.margin) * self.stone.body.r_max;
        self.stone.tree.decided_flock(&s.down, level, &self.stone.facet_flock)
    }
}

impl Certificate for EnergyCertificate<'_> {
    fn decided(&self, s: &BodyState) -> Option<Decided> {
        // O(1): too much energy for any decision (exact, see `decision_ceiling`).
        if (s.level + self.margin) * self.stone.body.r_max >= self.ceiling {
            return None;
        }
        if self.flock_level {
            self.flock(s).map(|k| Decided::Flock(k as u32))
        } else {
            self.facet(s).map(Decided::Facet)
        }
    }
}

/// What [`CERTIFICATE_MARGIN`] must cover, along one run: given per step the energy level L(t)
/// where the certificate may be asked (`Some`: contact relaxed, L ≤ 1 R_max; `None` elsewhere)
/// and the support height h(down(t)) (both R_max), the number of such steps and
/// max over them of (max over t' ≥ t of h(t')) − L(t), the largest later rise of h above a level
/// read (−∞ when no step may be asked). One backward pass: the running maximum of h from the end.
pub fn largest_later_rise(steps: &[(Option<f64>, f64)]) -> (u64, f64) {
    let (mut asked, mut rise, mut future_h) = (0, f64::NEG_INFINITY, f64::NEG_INFINITY);
    for &(level, h) in steps.iter().rev() {
        future_h = future_h.max(h);
        if let Some(l) = level {
            asked += 1;
            rise = rise.max(future_h - l);
        }
    }
    (asked, rise)
}

/// How the decisions a certificate makes along one run score against where the run ends.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct DecisionScore {
    /// Decisions made (states where the certificate decided).
    pub decisions: u64,
    /// Of those, the ones that name another outcome than the run's end.
    pub wrong: u64,
    /// Whether the first decision, the one a certified run would act on, was wrong (None: no
    /// decision).
    pub first_wrong: Option<bool>,
}

impl DecisionScore {
    /// The score of the decisions `decided` (in the order they were made, facets or flocks)
    /// against the run's end `truth`: a decision is wrong when it is not `truth`.
    pub fn of(decided: impl IntoIterator<Item = u32>, truth: Option<u32>) -> Self {
        let mut score = DecisionScore::default();
        for d in decided {
            let wrong = Some(d) != truth;
            (score.decisions, score.wrong) = (score.decisions + 1, score.wrong + u64::from(wrong));
            score.first_wrong.get_or_insert(wrong);
        }
        score
    }
}

/// The certificate of `mode` on `stone` (a no-op for [`CertificateMode::None`]).
pub fn certificate(stone: &Stone, mode: CertificateMode) -> Box<dyn Certificate + '_> {
    match EnergyCertificate::new(stone, mode) {
        Some(c) => Box::new(c),
        None => Box::new(NoCertificate),
    }
}

/// What the certificate's two bounds must cover along one run, read state by state
/// ([`CompressionWatch::see`]): the largest compression of the soft contact h(down) − z_G (R_max)
/// over the run and at its last state (to set against [`CERTIFICATE_MAX_COMPRESSION`] and the
/// rest tolerance), and the largest rise of the energy level L between two relaxed states
/// (compression ≤ [`CERTIFICATE_MAX_COMPRESSION`]) once L ≤ 1 R_max, where the certificate
/// decides: L minus the lowest L of such states so far (to set against [`CERTIFICATE_MARGIN`]).
#[derive(Clone, Copy, Debug)]
pub struct CompressionWatch {
    /// The largest h(down) − z_G seen (0 before any state, since h ≥ z_G at no compression).
    pub compression: f64,
    /// h(down) − z_G at the last state seen (NaN before any).
    pub last_compression: f64,
    /// The largest rise of L between relaxed states with L ≤ 1 R_max (0 if none).
    pub rise: f64,
    /// The lowest such L so far.
    low: f64,
}

impl Default for CompressionWatch {
    fn default() -> Self {
        CompressionWatch { compression: 0.0, last_compression: f64::NAN, rise: 0.0, low: f64::INFINITY }
    }
}

impl CompressionWatch {
    /// Read one state `s` of `body` (h(down) by the exact support function).
    pub fn see(&mut self, body: &crate::dynamics::engine::body::Body, s: &BodyState) {
        let c = body.support(&s.down) - s.z;
        self.compression = self.compression.max(c);
        if c <= CERTIFICATE_MAX_COMPRESSION && s.level <= 1.0 {
            self.low = self.low.min(s.level);
            self.rise = self.rise.max(s.level - self.low);
        }
        self.last_compression = c;
    }
}

/// The first decision a certificate makes along a run, asked at every step and asked only every
/// [`CERTIFICATE_EVERY`] steps as runs ask it: the step (counted from 1) and the facet or flock
/// decided. With a check every step a run would end at the first, as it does at the second.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct FirstDecision {
    /// The first decision, asked at every step.
    pub every_step: Option<(u64, u32)>,
    /// The first decision at a step that is a multiple of [`CERTIFICATE_EVERY`].
    pub every_k: Option<(u64, u32)>,
}

impl FirstDecision {
    /// Ask `cert` in state `s`, reached at step `step` (from 1), unless both first decisions are
    /// already known.
    pub fn ask(&mut self, cert: &dyn Certificate, step: u64, s: &BodyState) {
        if self.every_k.is_some() {
            return;
        }
        let Some(d) = cert.decided(s).map(Decided::id) else { return };
        self.every_step.get_or_insert((step, d));
        if step % CERTIFICATE_EVERY == 0 {
            self.every_k = Some((step, d));
        }
    }
}

/// [`DecisionScore`]s summed over runs: the decisions, the wrong ones, the runs with a decision
/// (a first one) and the runs whose first decision was wrong.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct DecisionTally {
    /// Decisions made, over every run.
    pub decisions: u64,
    /// Of those, the wrong ones.
    pub wrong: u64,
    /// Runs with at least one decision.
    pub first: u64,
    /// Runs whose first decision was wrong.
    pub first_wrong: u64,
}

impl DecisionTally {
    /// Count one run's score.
    pub fn add(&mut self, s: &DecisionScore) {
        let first = (u64::from(s.first_wrong.is_some()), u64::from(s.first_wrong == Some(true)));
        self.merge(&DecisionTally { decisions: s.decisions, wrong: s.wrong, first: first.0, first_wrong: first.1 });
    }

    /// Add the counts of another tally.
    pub fn merge(&mut self, o: &DecisionTally) {
        self.decisions += o.decisions;
        self.wrong += o.wrong;
        self.first += o.first;
        self.first_wrong += o.first_wrong;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn decisions_score_against_the_end() {
        // Ends on 3: one wrong decision (5) of four, and the first (3) right.
        let s = DecisionScore::of([3, 5, 3, 3], Some(3));
        assert_eq!(s, DecisionScore { decisions: 4, wrong: 1, first_wrong: Some(false) });
        // A first decision that is wrong; an end outside any flock makes every decision wrong.
        assert_eq!(DecisionScore::of([5, 3], Some(3)).first_wrong, Some(true));
        assert_eq!(DecisionScore::of([2, 2], None), DecisionScore { decisions: 2, wrong: 2, first_wrong: Some(true) });
        assert_eq!(DecisionScore::of([], Some(1)), DecisionScore::default());
    }

    #[test]
    fn the_later_rise_by_hand_and_by_every_pair() {
        // Asked at steps 0 and 2: h rises to 0.7 after step 0 (0.7 − 0.5) and to 0.55 after step 2.
        let steps = [(Some(0.5), 0.4), (None, 0.7), (Some(0.6), 0.55), (None, 0.3)];
        let (asked, rise) = largest_later_rise(&steps);
        assert_eq!(asked, 2);
        assert!((rise - 0.2).abs() < 1e-15, "{rise}");
        assert_eq!(largest_later_rise(&[(None, 1.0)]), (0, f64::NEG_INFINITY));
        // Against the definition over every pair t ≤ t' of a pseudo-random run.
        let steps: Vec<(Option<f64>, f64)> = (0..60u32)
            .map(|k| ((k % 3 != 1).then_some((k * 37 % 11) as f64 / 11.0), (k * 53 % 17) as f64 / 17.0))
            .collect();
        let pairs = (0..steps.len()).filter_map(|t| {
            let later = steps[t..].iter().map(|s| s.1).fold(f64::NEG_INFINITY, f64::max);
            steps[t].0.map(|l| later - l)
        });
        let want = pairs.fold(f64::NEG_INFINITY, f64::max);
        assert_eq!(largest_later_rise(&steps), (40, want));
    }

    /// A state facing straight down at height `z` with energy level `level` (at rest otherwise).
    fn state(z: f64, level: f64) -> BodyState {
        let zero = crate::Vec3::zeros();
        BodyState { down: -crate::Vec3::z(), z, linvel: zero, angvel: zero, level }
    }

    #[test]
    fn the_watch_reads_compressions_and_the_rise_of_the_level() {
        let cube = crate::generate::cuboid(1.0, 1.0, 1.0).into_solid_boundary().unwrap();
        let a = crate::analysis::Analysis::of_solid(cube.0, cube.1, &Default::default()).unwrap();
        let stone = Stone::new(&a, 0.0035).unwrap();
        let h = stone.body.support(&-crate::Vec3::z());
        let mut watch = CompressionWatch::default();
        // Compressed by 0.05 (not relaxed), then relaxed at L = 0.9, 0.4, 0.7 (rise 0.3), then
        // L = 1.5 (above 1 R_max: not counted), and last a compression of 5·10⁻⁴.
        let states = [(0.05, 0.9), (0.0, 0.9), (0.0, 0.4), (-0.01, 0.7), (0.0, 1.5), (5e-4, 0.6)];
        for (c, level) in states {
            watch.see(&stone.body, &state(h - c, level));
        }
        assert!((watch.compression - 0.05).abs() < 1e-12, "{}", watch.compression);
        assert!((watch.last_compression - 5e-4).abs() < 1e-12);
        assert!((watch.rise - 0.3).abs() < 1e-12, "{}", watch.rise);
    }

    /// Decides facet 7 once the level is under 0.5.
    struct Below;
    impl Certificate for Below {
        fn decided(&self, s: &BodyState) -> Option<Decided> {
            (s.level < 0.5).then_some(Decided::Facet(7))
        }
    }

    #[test]
    fn the_first_decisions_every_step_and_every_k_steps() {
        let mut first = FirstDecision::default();
        // Decided from step 6 on: the first at step 6, the first checked one at step 8 (= 2·4).
        for step in 1..=12u64 {
            first.ask(&Below, step, &state(0.0, if step >= 6 { 0.2 } else { 0.8 }));
        }
        assert_eq!(first, FirstDecision { every_step: Some((6, 7)), every_k: Some((2 * CERTIFICATE_EVERY, 7)) });
        let mut never = FirstDecision::default();
        (1..=12).for_each(|step| never.ask(&Below, step, &state(0.0, 0.8)));
        assert_eq!(never, FirstDecision::default());
    }

    #[test]
    fn a_tally_sums_scores_over_runs() {
        let mut tally = DecisionTally::default();
        // Runs: 4 decisions (1 wrong, first right), 2 (first wrong), none.
        for s in [
            DecisionScore::of([3, 5, 3, 3], Some(3)),
            DecisionScore::of([5, 3], Some(3)),
            DecisionScore::of([], Some(1)),
        ] {
            tally.add(&s);
        }
        assert_eq!(tally, DecisionTally { decisions: 6, wrong: 2, first: 2, first_wrong: 1 });
        let mut twice = tally;
        twice.merge(&tally);
        assert_eq!(twice, DecisionTally { decisions: 12, wrong: 4, first: 4, first_wrong: 2 });
    }
}
