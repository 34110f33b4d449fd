//! Field studies and synthetic hand experiments (paper §1.2, §3, Table 2, Figure 12).
//!
//! The paper models the person who counts the equilibria of a pebble by hand with one number,
//! ν: pairs of equilibria closer than ν·R_max in R are not told apart, so the experimenter counts
//! the equilibria of G(ν), not of G(0). This module turns that into tools:
//!
//! * **Field study** ([`run_files`], [`field`]): every scan of a folder analysed in parallel by the
//!   same pipeline as `rocking analyze` ([`Analysis::of_file`] → [`Report`]), joined on its id
//!   (the file name without extension) with an optional metadata CSV ([`Metadata`]), one row per
//!   pebble ([`write_pebbles_csv`]: the `rocking analyze` columns unchanged, then S, U, H at a
//!   fixed ν, by default the paper's [`PAPER_NU`]) and one row per sample ([`summarize`],
//!   [`write_samples_csv`]).
//! * **Static synthetic hand experiment**: the counts of G(ν) at a given ν ([`CountCurve`] reads
//!   them for any ν from the recorded hierarchy without recomputation).
//! * **Dynamic synthetic hand experiment** ([`hand_experiment`], [`experimenter`]): a simulated
//!   person who sets the pebble down in a uniformly random orientation from a small height,
//!   `trials` times, and notes the distinct stable flocks it comes to rest in (drops in rapier3d,
//!   ended as soon as the final flock is certain, [`CertificateMode::Flock`]). Setting a pebble
//!   down can only find stable positions: unstable equilibria (balancing on a tip) cannot be
//!   found this way, so the dynamic experiment gives S only. Rests inside unstable or saddle
//!   flocks (rocking equilibria) are counted apart.
//! * **Synthetic populations** ([`synthetic_sample`], [`synthetic`]): N pebbles of
//!   [`generate::pebble`] whose axis ratios scatter around a target sample's mean c/b and c/a.
//! * **Fitting ν** ([`fit_nu()`], [`mod@fit_nu`]): the ν at which synthetic populations with the
//!   axis ratios of the paper's Table 2 samples reproduce the hand columns E(S), E(U), σ(S), σ(U)
//!   best.
//! * **Hand throws against predictions** ([`outcomes`]): the measured outcome counts of a die or
//!   stone thrown by hand, read from its folder, and the score of predicted frequencies against
//!   them (total variation distance against its sampling-noise level, χ²).
//! * The metadata CSV is read by [`metadata`]; everything written or drawn (CSV, tables, plots)
//!   is in [`crate::report::study`].
//!
//! [`Analysis::of_file`]: crate::analysis::Analysis::of_file
//! [`Report`]: crate::analysis::Report
//! [`PAPER_NU`]: crate::analysis::PAPER_NU
//! [`CertificateMode::Flock`]: crate::dynamics::certificate::CertificateMode::Flock
//! [`generate::pebble`]: crate::generate::pebble
//! [`write_pebbles_csv`]: crate::report::study::write_pebbles_csv
//! [`write_samples_csv`]: crate::report::study::write_samples_csv
//!
//! **Standard deviations.** σ is the *sample* standard deviation (divisor n − 1) throughout. This
//! is the paper's convention for its hand columns, inferred from Table 2: a mean of 50 integer
//! counts is a multiple of 0.02 and the sum of squares Q of integers has the parity of their sum,
//! so for each (E, σ) pair one can ask whether any integer Q reproduces σ to the printed two
//! decimals. For all 44 hand pairs the n − 1 divisor admits such a Q; the population divisor
//! (n) admits none for 28 of them. (The paper's computer columns, 20 pebbles, fit the population
//! divisor better: 5 of the 6 decisive pairs.)

pub mod experimenter;
pub mod field;
pub mod fit_hand;
pub mod fit_nu;
pub mod hand;
pub mod hand_table2;
pub mod metadata;
pub mod outcomes;
pub mod synthetic;

pub use experimenter::*;
pub use field::*;
pub use fit_hand::*;
pub use fit_nu::*;
pub use hand::*;
pub use hand_table2::*;
pub use metadata::*;
pub use synthetic::*;

use crate::equilibria::Kind;
use crate::hierarchy::{Counts, Hierarchy};
use crate::stats::{mean, sample_sd};
use serde::Serialize;

/// E and σ (sample standard deviation) of S and U over a group of pebbles.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Moments {
    /// Number of pebbles.
    pub n: usize,
    /// E(S): mean number of stable equilibria.
    pub es: f64,
    /// E(U): mean number of unstable equilibria.
    pub eu: f64,
    /// σ(S): sample standard deviation of S.
    pub sd_s: f64,
    /// σ(U): sample standard deviation of U.
    pub sd_u: f64,
}

impl Moments {
    /// Moments of the (S, U) pairs.
    pub fn of(su: &[(f64, f64)]) -> Moments {
        let s: Vec<f64> = su.iter().map(|p| p.0).collect();
        let u: Vec<f64> = su.iter().map(|p| p.1).collect();
        Moments { n: su.len(), es: mean(&s), eu: mean(&u), sd_s: sample_sd(&s), sd_u: sample_sd(&u) }
    }

    /// Moments of the stable and unstable counts.
    pub fn of_counts(c: &[Counts]) -> Moments {
        Moments::of(&c.iter().map(|c| (c.stable as f64, c.unstable as f64)).collect::<Vec<_>>())
    }

    /// [E(S), E(U), σ(S), σ(U)].
    pub fn as_array(&self) -> [f64; 4] {
        [self.es, self.eu, self.sd_s, self.sd_u]
    }
}

/// S(ν), U(ν), H(ν) of one stone for every ν, read from its cancellation hierarchy: the counts
/// of G(0) and after every distinct level. `at(ν)` equals [`Hierarchy::counts_at`] (cancellations
/// with level < ν applied), in O(log n).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct CountCurve {
    /// Distinct cancellation levels, increasing.
    pub levels: Vec<f64>,
    /// `counts[0]` = G(0); `counts[k]` = after every cancellation with level ≤ `levels[k − 1]`.
    pub counts: Vec<Counts>,
}

impl CountCurve {
    /// Record the curve of a hierarchy.
    pub fn of(h: &Hierarchy) -> CountCurve {
        let mut c = h.counts0();
        let mut levels = Vec::new();
        let mut counts = vec![c];
        let mut i = 0;
        while i < h.cancellations.len() {
            let level = h.cancellations[i].level;
            while i < h.cancellations.len() && h.cancellations[i].level == level {
                for &x in &h.cancellations[i].removed {
                    let slot = match h.nodes[x].kind {
                        Kind::Stable => &mut c.stable,
                        Kind::Unstable => &mut c.unstable,
                        Kind::Saddle => &mut c.saddle,
                    };
                    *slot -= 1;
                }
                i += 1;
            }
            levels.push(level);
            counts.push(c);
        }
        CountCurve { levels, counts }
    }

    /// The counts of G(ν).
    pub fn at(&self, nu: f64) -> Counts {
        self.counts[self.levels.partition_point(|&l| l < nu)]
    }

    /// The counts of G(0): the micro-equilibria.
    pub fn micro(&self) -> Counts {
        self.counts[0]
    }
}
