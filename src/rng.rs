//! Reproducible randomness: one independent stream per item of a run, and the random and
//! quasi-random directions and rotations drawn from it.
//!
//! Item i of a run seeded with s (a drop, a push trial, a synthetic pebble) draws everything from
//! its own generator, Xoshiro256++ seeded with SplitMix64(SplitMix64(s) ⊕ i) ([`item_rng`]). So
//! the result of item i does not depend on the thread count, the order of execution, the batch
//! size or how a run is sharded.

use crate::Vec3;
use nalgebra::{Quaternion, UnitQuaternion};
use rand::{Rng, RngExt, SeedableRng};
use rand_distr::StandardNormal;
use rand_xoshiro::Xoshiro256PlusPlus;
use std::f64::consts::PI;

/// The generator of every stream (a named, version-stable algorithm).
pub type Stream = Xoshiro256PlusPlus;

/// SplitMix64 finaliser: a bijective mix of 64 bits.
pub fn splitmix(mut z: u64) -> u64 {
    z = z.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// The random stream of item `index` of a run seeded with `seed`.
pub fn item_rng(seed: u64, index: u64) -> Stream {
    Xoshiro256PlusPlus::seed_from_u64(splitmix(splitmix(seed) ^ index))
}

/// FNV-1a (64 bit) over a byte sequence: a stable hash for seeds and fingerprints (not for
/// security).
pub fn fnv1a(bytes: impl IntoIterator<Item = u8>) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for b in bytes {
        h ^= b as u64;
        h = h.wrapping_mul(0x0100_0000_01b3);
    }
    h
}

/// FNV-1a of a string (mixes a name into a seed, e.g. a pebble's id).
pub fn fnv1a_str(s: &str) -> u64 {
    fnv1a(s.bytes())
}

/// A uniformly random unit quaternion: four independent standard normals, normalised (uniform on
/// S³, i.e. Haar-uniform on SO(3)).
pub fn random_rotation<R: Rng + ?Sized>(rng: &mut R) -> UnitQuaternion<f64> {
    let mut g = || rng.sample::<f64, _>(StandardNormal);
    UnitQuaternion::from_quaternion(Quaternion::new(g(), g(), g(), g()))
}

/// A uniformly random unit vector: a standard normal triple, normalised (redrawn in the
/// measure-zero case of a near-zero triple).
pub fn random_unit<R: Rng + ?Sized>(rng: &mut R) -> Vec3 {
    loop {
        let v = Vec3::from_fn(|_, _| rng.sample::<f64, _>(StandardNormal));
        let n = v.norm();
        if n > 1e-9 {
            return v / n;
        }
    }
}

/// `n` quasi-uniform unit directions, the Fibonacci sphere: zₖ = 1 − (2k+1)/n, θₖ = k·π(3 − √5)
/// (the golden angle).
pub fn fibonacci_sphere(n: usize) -> Vec<Vec3> {
    let golden = PI * (3.0 - 5f64.sqrt());
    (0..n)
        .map(|k| {
            let z = 1.0 - (2 * k + 1) as f64 / n as f64;
            let rho = (1.0 - z * z).max(0.0).sqrt();
            let t = golden * k as f64;
            Vec3::new(rho * t.cos(), rho * t.sin(), z)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn streams_depend_only_on_seed_and_index() {
        let a: Vec<u64> = (0..5).map(|i| item_rng(7, i).next_u64()).collect();
        let b: Vec<u64> =
            (0..5).rev().map(|i| item_rng(7, i).next_u64()).collect::<Vec<_>>().into_iter().rev().collect();
        assert_eq!(a, b);
        assert_ne!(item_rng(7, 0).next_u64(), item_rng(8, 0).next_u64());
        assert_ne!(a[0], a[1]);
    }

    #[test]
    fn fnv1a_matches_the_published_test_vectors() {
        // FNV-1a 64: "" → cbf29ce484222325, "a" → af63dc4c8601ec8c, "foobar" → 85944171f73967e8.
        assert_eq!(fnv1a_str(""), 0xcbf2_9ce4_8422_2325);
        assert_eq!(fnv1a_str("a"), 0xaf63_dc4c_8601_ec8c);
        assert_eq!(fnv1a_str("foobar"), 0x8594_4171_f739_67e8);
    }

    #[test]
    fn random_units_are_unit_and_centred() {
        let mut rng = item_rng(1, 2);
        let v: Vec<Vec3> = (0..20000).map(|_| random_unit(&mut rng)).collect();
        assert!(v.iter().all(|u| (u.norm() - 1.0).abs() < 1e-12));
        // The mean of uniform unit vectors is 0 with σ = 1/√(3n) ≈ 0.0041 per component.
        let m = v.iter().sum::<Vec3>() / v.len() as f64;
        assert!(m.norm() < 0.02, "{m}");
        let f = fibonacci_sphere(1000);
        assert!((f.iter().sum::<Vec3>() / 1000.0).norm() < 1e-3);
    }
}
