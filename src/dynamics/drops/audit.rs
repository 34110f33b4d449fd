//! The energy certificate audited along one drop: the drop is simulated to rest without a
//! certificate while the facet- and the flock-level certificate are asked along it as a
//! certified run would ask them. Their decisions are scored against where the drop rests
//! ([`DecisionScore`]), and the largest later rise of the support height above the energy level
//! read at any state where a certificate may be asked is what
//! [`crate::dynamics::certificate::CERTIFICATE_MARGIN`] must cover ([`largest_later_rise`]).

use crate::dynamics::certificate::{largest_later_rise, DecisionScore, EnergyCertificate};
use crate::dynamics::drops::alone::simulate_observed;
use crate::dynamics::drops::launch::Release;
use crate::dynamics::drops::params::DropParams;
use crate::dynamics::engine::run::{Certificate, Decided, CERTIFICATE_EVERY};
use crate::dynamics::stone::Stone;

/// What asking the certificates along one drop found.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CertificateAudit {
    /// The stable facet the drop rests on after full settling.
    pub facet: u32,
    /// The decisions of the facet and of the flock certificate (in that order), scored against
    /// that facet and its flock.
    pub scores: [DecisionScore; 2],
    /// The states where a certificate may be asked: contact relaxed, L ≤ 1 R_max.
    pub asked: u64,
    /// The largest later rise of h(down) above the L read at one of them (R_max; −∞ if none).
    pub excess: f64,
}

/// Simulate drop `index`, released as `release`, of `stone` under `p` to rest without a
/// certificate ([`simulate_observed`]: a batch of one, so with the flight of `p`), asking the
/// certificates `[facet, flock]` every [`CERTIFICATE_EVERY`] steps, and reading at every step
/// h(down) (by hill climbing) and, where the facet certificate finds the contact relaxed and
/// L ≤ 1 R_max, the level L. None if the run ends on no facet.
pub fn audit_certificates(
    stone: &Stone,
    p: &DropParams,
    [facet, flock]: [&EnergyCertificate; 2],
    release: &Release,
    index: u64,
) -> Option<CertificateAudit> {
    // Per step: the decisions (facet, flock) where asked, and (L if a certificate may be asked, h).
    let (mut decided, mut levels, mut step) = (Vec::<[Option<u32>; 2]>::new(), Vec::new(), 0u64);
    let outcome = simulate_observed(stone, p, release, index, &mut |s| {
        step += 1;
        let h = stone.body.support_climb(&s.down);
        levels.push(((facet.relaxed(s) && s.level <= 1.0).then_some(s.level), h));
        if step % CERTIFICATE_EVERY == 0 {
            decided.push([facet.decided(s).and_then(Decided::facet), flock.decided(s).and_then(Decided::flock)]);
        }
    });
    let facet = outcome?.facet?;
    let truth = [Some(facet), stone.flock_of(facet).map(|k| k as u32)];
    let scores = std::array::from_fn(|l| DecisionScore::of(decided.iter().filter_map(|d| d[l]), truth[l]));
    let (asked, excess) = largest_later_rise(&levels);
    Some(CertificateAudit { facet, scores, asked, excess })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::{Analysis, Options};
    use crate::dynamics::certificate::{CertificateMode, CERTIFICATE_MARGIN};
    use crate::dynamics::drops::{launch::launch, params::Preset, simulate::simulate};
    use crate::dynamics::engine::run::NoCertificate;
    use crate::dynamics::surface::Surface;

    #[test]
    fn audited_box_drops_rest_where_simulated_and_their_decisions_are_right() {
        let (mesh, repairs) = crate::generate::cuboid(1.0, 0.8, 0.5).into_solid_boundary().unwrap();
        let stone = Stone::new(&Analysis::of_solid(mesh, repairs, &Options::default()).unwrap(), 0.0035).unwrap();
        let p = Preset::Drop.params(Surface::SteelOnWood);
        let [facet, flock] =
            [CertificateMode::Facet, CertificateMode::Flock].map(|m| EnergyCertificate::new(&stone, m).unwrap());
        for i in 0..4 {
            let release = launch(&mut crate::rng::item_rng(9, i), &p);
            let audit = audit_certificates(&stone, &p, [&facet, &flock], &release, i).unwrap();
            assert_eq!(Some(audit.facet), simulate(&stone, &p, &release, i, &NoCertificate).facet, "drop {i}");
            // A box at rest on a face is certain of it: decisions, and none wrong.
            for s in audit.scores {
                assert!(s.decisions > 0 && s.wrong == 0 && s.first_wrong == Some(false), "drop {i}: {s:?}");
            }
            assert!(audit.asked > 0 && audit.excess < CERTIFICATE_MARGIN, "drop {i}: {audit:?}");
        }
    }
}
