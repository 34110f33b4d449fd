//! Recorded and synthetic ground motion: three-component acceleration histories, their readers,
//! intensity measures and the fragility surface of precariously balanced rocks.
//!
//! A [`Record`] is the ground acceleration of a site sampled at a uniform interval `dt` (s, real
//! time), in m/s², with components `[x, y, z]`: two horizontal components and the vertical one (z
//! up). Readers turn the formats seismologists use into records ([`read`]: CSV with named
//! columns, PEER NGA `.AT2`); [`synthetic`] makes the test motions (one-sine pulses, filtered
//! noise); [`fragility`] fits P(overturn | PGA, PGV/PGA), [`studies`] checks its band over repeated
//! studies.
//!
//! This module knows nothing of stones: the dynamics read a record through [`Record::at`].
//!
//! # Intensity measures
//!
//! For a record a(t) with horizontal part a_h = (a_x, a_y) ([`Record::measures`]):
//!
//! ```text
//! PGA = max_t |a_h(t)|,    PGV = max_t |v_h(t)|,    PGV/PGA (s),
//! ```
//!
//! the peaks of the horizontal resultant (for a one-component record, the usual peaks of that
//! component). PGA is read from the record as given. PGV is read from the ground velocity v as
//! strong-motion processing computes it ([`processing`]): the mean removed, zero pads, an acausal
//! Butterworth high-pass (order 5 per pass, corner 0.08 Hz by default, the zero-phase response
//! 1/(1 + (f_c/f)^10)), then the trapezoid rule — not from the plain integral
//! ([`Record::velocity`]), which drifts with any offset or long-period noise of the record. A
//! record whose PGV is known says so ([`Record::with_known_pgv`]: a measurement, or the closed
//! form of a synthetic pulse); its measures then carry that PGV, scaled with the record, and
//! [`Measures::pgv_source`] says which was used. PGV/PGA is the second variable of the fragility
//! surfaces of Purvance, Anooshehpoor & Brune (2008).

pub mod fragility;
pub mod processing;
pub mod read;
pub mod studies;
pub mod synthetic;

use crate::{Error, Result, GRAVITY as G};
use processing::Processing;
use realfft::RealFftPlanner;
use serde::{Deserialize, Serialize};

/// A ground-acceleration history: uniform sampling from t = 0, three components (m/s²).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Record {
    /// Name of the record (a file name, or the synthetic motion's description).
    pub name: String,
    /// Sampling interval (s, real time).
    pub dt: f64,
    /// Acceleration at t = k·dt: `[x, y, z]` in m/s², x and y horizontal, z up.
    pub accel: Vec<[f64; 3]>,
    /// The record's peak horizontal ground velocity (m/s) when it is known (measured, or the
    /// closed form of a synthetic motion): [`Record::measures`] then reports it instead of the
    /// processed one. Set with [`Record::with_known_pgv`]; scales with [`Record::scaled`].
    #[serde(skip_serializing_if = "Option::is_none")]
    pub known_pgv_m_s: Option<f64>,
}

/// Where the PGV of [`Measures`] comes from.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum PgvSource {
    /// The velocity of standard strong-motion processing ([`processing`]).
    #[default]
    Processed,
    /// Given with the record ([`Record::with_known_pgv`]).
    Given,
}

impl PgvSource {
    /// The word a summary prints: `processed` or `given`.
    pub fn name(self) -> &'static str {
        match self {
            PgvSource::Processed => "processed",
            PgvSource::Given => "given",
        }
    }
}

/// Peak values of a record ([`Record::measures`]).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Measures {
    /// Peak horizontal ground acceleration (m/s²).
    pub pga_m_s2: f64,
    /// Peak horizontal ground acceleration (g).
    pub pga_g: f64,
    /// Peak horizontal ground velocity (m/s): of the velocity after strong-motion processing
    /// (mean removed, zero pads, acausal Butterworth high-pass of order 5 at 0.08 Hz, see
    /// [`processing`]), or the record's known PGV ([`Measures::pgv_source`]).
    pub pgv_m_s: f64,
    /// PGV / PGA (s): a time scale of the strong pulses.
    pub pgv_over_pga_s: f64,
    /// Peak vertical acceleration (g).
    pub pga_vertical_g: f64,
    /// Duration (s).
    pub duration_s: f64,
    /// Which PGV this is: processed, or given with the record.
    pub pgv_source: PgvSource,
}

/// A record × scale factor and the intensity measures of the scaled record: what one field-rock
/// run or ensemble was shaken with.
#[derive(Clone, Debug, PartialEq, Serialize, serde::Deserialize)]
pub struct ScaledRecord {
    /// Name of the record.
    pub record: String,
    /// Scale factor applied to the record.
    pub scale: f64,
    /// Peak horizontal ground acceleration of the scaled record (g).
    pub pga_g: f64,
    /// Peak horizontal ground velocity of the scaled record (m/s), as [`Measures::pgv_m_s`].
    pub pgv_m_s: f64,
    /// PGV/PGA (s).
    pub pgv_over_pga_s: f64,
    /// Peak vertical ground acceleration (g).
    pub pga_vertical_g: f64,
    /// Which PGV this is: processed, or given with the record (absent in journals written before
    /// it was recorded: processed).
    #[serde(default)]
    pub pgv_source: PgvSource,
}

impl ScaledRecord {
    /// `record` × `scale`, its scaled record's measures `m`.
    pub fn of(record: &Record, scale: f64, m: &Measures) -> ScaledRecord {
        let (pga_g, pgv_m_s, pgv_over_pga_s, pga_vertical_g) = (m.pga_g, m.pgv_m_s, m.pgv_over_pga_s, m.pga_vertical_g);
        let pgv_source = m.pgv_source;
        ScaledRecord { record: record.name.clone(), scale, pga_g, pgv_m_s, pgv_over_pga_s, pga_vertical_g, pgv_source }
    }

    /// Whether `other` is the same record at the same scale factor (bit for bit): a run of the
    /// same case, whatever the rock or the member.
    pub fn same_as(&self, other: &ScaledRecord) -> bool {
        self.record == other.record && self.scale.to_bits() == other.scale.to_bits()
    }
}

impl Record {
    /// A record from its samples; refuses fewer than two samples, a non-positive or non-finite
    /// interval and non-finite values (naming the sample).
    pub fn new(name: impl Into<String>, dt: f64, accel: Vec<[f64; 3]>) -> Result<Record> {
        let name = name.into();
        if !(dt > 0.0 && dt.is_finite()) {
            return Err(Error::motion(name, format!("the sampling interval must be positive, got {dt} s")));
        }
        if accel.len() < 2 {
            return Err(Error::motion(name, format!("a record needs at least two samples, got {}", accel.len())));
        }
        if let Some(k) = accel.iter().position(|a| a.iter().any(|x| !x.is_finite())) {
            return Err(Error::motion(
                name,
                format!("sample {} (t = {} s) is not a finite number", k + 1, k as f64 * dt),
            ));
        }
        Ok(Record { name, dt, accel, known_pgv_m_s: None })
    }

    /// The record with its peak horizontal ground velocity known to be `pgv_m_s` (m/s, > 0): a
    /// measured PGV, or the closed form of a synthetic motion. [`Record::measures`] reports it
    /// (source [`PgvSource::Given`]) instead of the processed one.
    pub fn with_known_pgv(self, pgv_m_s: f64) -> Result<Record> {
        if !(pgv_m_s > 0.0 && pgv_m_s.is_finite()) {
            return Err(Error::parameter("pgv", format!("{pgv_m_s} m/s"), "a positive peak ground velocity (m/s)"));
        }
        Ok(Record { known_pgv_m_s: Some(pgv_m_s), ..self })
    }

    /// The same record (name, known PGV) with other samples: `accel` at interval `dt`.
    fn with_samples(&self, dt: f64, accel: Vec<[f64; 3]>) -> Record {
        Record { name: self.name.clone(), dt, accel, known_pgv_m_s: self.known_pgv_m_s }
    }

    /// Duration (s): the time of the last sample.
    pub fn duration(&self) -> f64 {
        (self.accel.len().saturating_sub(1)) as f64 * self.dt
    }

    /// Acceleration (m/s²) at time `t` (s): linear interpolation between samples, zero before
    /// the first and after the last.
    pub fn at(&self, t: f64) -> [f64; 3] {
        let n = self.accel.len();
        if n == 0 || t < 0.0 || t > self.duration() || t.is_nan() {
            return [0.0; 3];
        }
        let x = t / self.dt;
        let k = (x.floor() as usize).min(n - 2);
        let s = x - k as f64;
        let (a, b) = (self.accel[k], self.accel[k + 1]);
        [a[0] + s * (b[0] - a[0]), a[1] + s * (b[1] - a[1]), a[2] + s * (b[2] - a[2])]
    }

    /// The record multiplied by `factor` (a scaled earthquake).
    pub fn scaled(&self, factor: f64) -> Record {
        let accel = self.accel.iter().map(|a| a.map(|x| x * factor)).collect();
        let known_pgv_m_s = self.known_pgv_m_s.map(|v| v * factor.abs());
        Record { known_pgv_m_s, ..self.with_samples(self.dt, accel) }
    }

    /// The record scaled to peak horizontal acceleration `pga_g` (g); a record without
    /// horizontal motion is returned unchanged.
    pub fn scaled_to_pga(&self, pga_g: f64) -> Record {
        let peak = self.pga_m_s2() / G;
        if peak > 0.0 {
            self.scaled(pga_g / peak)
        } else {
            self.clone()
        }
    }

    /// The horizontal components turned by `azimuth` (rad, counter-clockwise seen from above):
    /// the record's x axis then points along (cos φ, sin φ, 0) of the world.
    pub fn rotated(&self, azimuth: f64) -> Record {
        let (s, c) = azimuth.sin_cos();
        let accel = self.accel.iter().map(|a| [c * a[0] - s * a[1], s * a[0] + c * a[1], a[2]]).collect();
        self.with_samples(self.dt, accel)
    }

    /// Ground velocity (m/s) at every sample: the trapezoid rule from v(0) = 0 on the record as
    /// given, without baseline correction or filtering (PGV is read from [`Record::processed`]).
    pub fn velocity(&self) -> Vec<[f64; 3]> {
        trapezoid(self.dt, &self.accel)
    }

    /// Peak horizontal acceleration (m/s²) of the record as given.
    fn pga_m_s2(&self) -> f64 {
        self.accel.iter().map(|a| a[0].hypot(a[1])).fold(0.0, f64::max)
    }

    /// PGA, PGV and PGV/PGA (see the module doc): PGV the record's known one, else that of the
    /// velocity processed with the default [`Processing`].
    pub fn measures(&self) -> Measures {
        let (pgv, pgv_source) = match self.known_pgv_m_s {
            Some(v) => (v, PgvSource::Given),
            None => (self.processed_unchecked(&Processing::default()).pgv(), PgvSource::Processed),
        };
        self.measures_with_pgv(pgv, pgv_source)
    }

    /// [`Record::measures`] with PGV from the velocity processed with `p` (checked), whether or
    /// not the record's PGV is known.
    pub fn measures_processed(&self, p: &Processing) -> Result<Measures> {
        Ok(self.measures_with_pgv(self.processed(p)?.pgv(), PgvSource::Processed))
    }

    fn measures_with_pgv(&self, pgv: f64, pgv_source: PgvSource) -> Measures {
        let pga = self.pga_m_s2();
        let vertical = self.accel.iter().map(|a| a[2].abs()).fold(0.0, f64::max);
        Measures {
            pga_m_s2: pga,
            pga_g: pga / G,
            pgv_m_s: pgv,
            pgv_over_pga_s: if pga > 0.0 { pgv / pga } else { 0.0 },
            pga_vertical_g: vertical / G,
            duration_s: self.duration(),
            pgv_source,
        }
    }

    /// Baseline correction: the velocity v(t) integrated from the record is fitted by least
    /// squares with a polynomial P of degree `order` in t (0–3), and P′ is removed from the
    /// acceleration, component by component: a_c = a − P′. Order 1 removes a constant offset of
    /// the acceleration (the commonest baseline error, which makes v grow linearly), order 2 a
    /// linear drift; order 0 changes nothing (P′ = 0). The correction is the classical
    /// polynomial baseline fit (Boore & Bommer 2005, §4), applied to the velocity.
    pub fn baseline_corrected(&self, order: usize) -> Result<Record> {
        if order > 3 {
            return Err(Error::parameter("baseline", order, "a polynomial order from 0 to 3"));
        }
        let v = self.velocity();
        let n = self.accel.len();
        let span = self.duration().max(self.dt);
        // Fit in the normalised time u = t / span ∈ [0, 1] (well conditioned).
        let u: Vec<f64> = (0..n).map(|k| k as f64 * self.dt / span).collect();
        let m = order + 1;
        let basis = |x: f64| -> Vec<f64> { (0..m).map(|j| x.powi(j as i32)).collect() };
        let mut ata = nalgebra::DMatrix::<f64>::zeros(m, m);
        for &x in &u {
            let b = basis(x);
            for i in 0..m {
                for j in 0..m {
                    ata[(i, j)] += b[i] * b[j];
                }
            }
        }
        let chol = ata
            .cholesky()
            .ok_or_else(|| Error::motion(&self.name, format!("too few samples for a baseline of order {order}")))?;
        let mut accel = self.accel.clone();
        for c in 0..3 {
            let mut atv = nalgebra::DVector::<f64>::zeros(m);
            for (x, vk) in u.iter().zip(&v) {
                for (j, bj) in basis(*x).iter().enumerate() {
                    atv[j] += bj * vk[c];
                }
            }
            let coef = chol.solve(&atv);
            for (a, &x) in accel.iter_mut().zip(&u) {
                // dP/dt = (1/span) Σ j c_j u^(j−1).
                let slope: f64 = (1..m).map(|j| j as f64 * coef[j] * x.powi(j as i32 - 1)).sum::<f64>() / span;
                a[c] -= slope;
            }
        }
        Ok(self.with_samples(self.dt, accel))
    }

    /// The record sampled at interval `dt` (s). When `dt` is coarser than the record's interval
    /// the record is first low-passed at the new Nyquist frequency 1/(2 dt) — its spectrum
    /// (FFT of the record padded with as many zeros, so nothing wraps around) is cut above
    /// 0.9 of the Nyquist frequency with a cosine taper up to it — so content above it cannot
    /// alias into the band the simulation sees; then it is interpolated linearly at the new
    /// times. A finer `dt` only interpolates (no new frequencies appear).
    pub fn resampled(&self, dt: f64) -> Result<Record> {
        if !(dt > 0.0 && dt.is_finite()) {
            return Err(Error::parameter("dt", format!("{dt} s"), "a positive resampling interval"));
        }
        let source = if dt > self.dt * (1.0 + 1e-12) { self.low_passed(0.5 / dt) } else { self.clone() };
        let n = (self.duration() / dt + 1e-9).floor() as usize + 1;
        let accel = (0..n.max(2)).map(|k| source.at(k as f64 * dt)).collect();
        Ok(self.with_samples(dt, accel))
    }

    /// The record with its spectrum removed above `f_cut` (Hz), tapered from 0.9 f_cut.
    fn low_passed(&self, f_cut: f64) -> Record {
        let n = self.accel.len();
        let len = 2 * n;
        let mut planner = RealFftPlanner::<f64>::new();
        let (fwd, inv) = (planner.plan_fft_forward(len), planner.plan_fft_inverse(len));
        let df = 1.0 / (len as f64 * self.dt);
        let mut accel = self.accel.clone();
        for c in 0..3 {
            let mut x = vec![0.0; len];
            for (xi, a) in x.iter_mut().zip(&self.accel) {
                *xi = a[c];
            }
            if x.iter().all(|v| *v == 0.0) {
                continue;
            }
            let mut spec = fwd.make_output_vec();
            fwd.process(&mut x, &mut spec).expect("lengths from the plan");
            for (k, s) in spec.iter_mut().enumerate() {
                let f = k as f64 * df;
                let w = if f <= 0.9 * f_cut {
                    1.0
                } else if f >= f_cut {
                    0.0
                } else {
                    0.5 * (1.0 + (std::f64::consts::PI * (f - 0.9 * f_cut) / (0.1 * f_cut)).cos())
                };
                *s *= w / len as f64;
            }
            // The inverse of a real signal's spectrum: the DC and Nyquist bins are real.
            spec[0].im = 0.0;
            if let Some(last) = spec.last_mut() {
                last.im = 0.0;
            }
            let mut out = inv.make_output_vec();
            inv.process(&mut spec, &mut out).expect("lengths from the plan");
            for (a, y) in accel.iter_mut().zip(&out) {
                a[c] = *y;
            }
        }
        self.with_samples(self.dt, accel)
    }
}

/// The running integral of `accel` sampled at `dt` by the trapezoid rule, from 0 at the first
/// sample.
fn trapezoid(dt: f64, accel: &[[f64; 3]]) -> Vec<[f64; 3]> {
    let mut v = Vec::with_capacity(accel.len());
    let mut cur = [0.0; 3];
    v.push(cur);
    for w in accel.windows(2) {
        for c in 0..3 {
            cur[c] += 0.5 * dt * (w[0][c] + w[1][c]);
        }
        v.push(cur);
    }
    v
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    fn sine(f: f64, dt: f64, duration: f64, amp: f64) -> Record {
        let n = (duration / dt).round() as usize + 1;
        let accel = (0..n).map(|k| [amp * (2.0 * PI * f * k as f64 * dt).sin(), 0.0, 0.0]).collect();
        Record::new("sine", dt, accel).unwrap()
    }

    fn rms_x(r: &Record, from: f64, to: f64) -> f64 {
        let v: Vec<f64> = r
            .accel
            .iter()
            .enumerate()
            .filter(|(k, _)| (from..to).contains(&(*k as f64 * r.dt)))
            .map(|(_, a)| a[0] * a[0])
            .collect();
        (v.iter().sum::<f64>() / v.len() as f64).sqrt()
    }

    #[test]
    fn interpolation_is_linear_and_zero_outside() {
        let r = Record::new("r", 0.5, vec![[0.0, 1.0, 2.0], [1.0, 3.0, -2.0], [3.0, 3.0, 0.0]]).unwrap();
        assert_eq!(r.duration(), 1.0);
        assert_eq!(r.at(0.25), [0.5, 2.0, 0.0]);
        assert_eq!(r.at(0.75), [2.0, 3.0, -1.0]);
        assert_eq!(r.at(1.0), [3.0, 3.0, 0.0]);
        assert_eq!(r.at(-0.1), [0.0; 3]);
        assert_eq!(r.at(1.1), [0.0; 3]);
    }

    #[test]
    fn bad_records_are_refused_with_the_sample() {
        let e = Record::new("quake.csv", 0.01, vec![[0.0; 3], [f64::NAN, 0.0, 0.0]]).unwrap_err().to_string();
        assert!(e.contains("quake.csv") && e.contains("sample 2"), "{e}");
        assert!(Record::new("r", 0.0, vec![[0.0; 3]; 3]).is_err());
        assert!(Record::new("r", 0.01, vec![[0.0; 3]]).is_err());
    }

    #[test]
    fn rotation_turns_the_horizontal_plane_only() {
        let r = Record::new("r", 0.1, vec![[1.0, 0.0, 0.5], [0.0, 2.0, 0.0]]).unwrap().rotated(PI / 2.0);
        let close = |a: [f64; 3], b: [f64; 3]| a.iter().zip(b).all(|(x, y)| (x - y).abs() < 1e-12);
        assert!(close(r.accel[0], [0.0, 1.0, 0.5]));
        assert!(close(r.accel[1], [-2.0, 0.0, 0.0]));
    }

    #[test]
    fn sine_cycles_have_closed_form_peaks() {
        // a = A sin(ωt) for whole cycles: PGA = A, v = (A/ω)(1 − cos ωt), PGV = 2A/ω.
        let (a, f) = (3.0, 2.0);
        let r = sine(f, 1e-3, 1.5, a);
        let pgv = 2.0 * a / (2.0 * PI * f);
        // The trapezoid rule is exact to (ω dt)²/12 = 1.3·10⁻⁵ here.
        let raw = r.velocity().iter().map(|v| v[0].abs()).fold(0.0, f64::max);
        assert!((raw - pgv).abs() < 2e-5 * pgv, "{raw} vs {pgv}");
        // Processed, the pulse's displacement goes with the high-pass: T f_c (π/10)/sin(π/10)
        // = 12.2 % of its peak (see `processing`).
        let m = r.measures();
        assert_eq!(m.pgv_source, PgvSource::Processed);
        assert!((m.pgv_m_s / pgv - (1.0 - 1.5 * 0.08 * 1.0166)).abs() < 5e-3, "{} vs {pgv}", m.pgv_m_s);
        assert!((m.pga_m_s2 - a).abs() < 1e-4 * a, "{m:?}");
        assert!((m.pga_g - a / G).abs() < 1e-4);
        // Known, the closed form is what the measures say.
        let m = r.with_known_pgv(pgv).unwrap().measures();
        assert_eq!((m.pgv_m_s, m.pgv_source), (pgv, PgvSource::Given));
        assert!((m.pgv_over_pga_s - 1.0 / (PI * f)).abs() < 1e-4, "{m:?}");
    }

    #[test]
    fn a_known_pgv_scales_with_the_record_and_survives_its_transformations() {
        let r = sine(1.0, 0.01, 4.0, 2.0).with_known_pgv(0.5).unwrap();
        assert_eq!(r.scaled(-2.0).measures().pgv_m_s, 1.0);
        assert!((r.scaled_to_pga(0.1).measures().pgv_m_s - 0.5 * 0.1 * G / 2.0).abs() < 1e-12);
        for other in [r.rotated(0.3), r.resampled(0.02).unwrap(), r.baseline_corrected(1).unwrap()] {
            assert_eq!(other.measures().pgv_m_s, 0.5);
        }
        // The processed PGV is still there to compare.
        let processed = r.measures_processed(&Processing::default()).unwrap();
        assert_eq!(processed.pgv_source, PgvSource::Processed);
        assert_eq!(processed.pgv_m_s, r.processed(&Processing::default()).unwrap().pgv());
        assert!(r.measures_processed(&Processing { corner_hz: -1.0, order: 5 }).is_err());
        for bad in [0.0, -1.0, f64::NAN, f64::INFINITY] {
            assert!(sine(1.0, 0.01, 1.0, 1.0).with_known_pgv(bad).is_err());
        }
    }

    #[test]
    fn horizontal_peaks_are_of_the_resultant() {
        // x = cos, y = sin: |a_h| = 1 at every sample although neither component alone says so.
        let n = 101;
        let accel = (0..n).map(|k| (k as f64 * 0.05).sin_cos()).map(|(s, c)| [c, s, 5.0]).collect();
        let m = Record::new("circle", 0.01, accel).unwrap().measures();
        assert!((m.pga_m_s2 - 1.0).abs() < 1e-12);
        assert!((m.pga_vertical_g - 5.0 / G).abs() < 1e-12);
    }

    #[test]
    fn baseline_removes_an_offset_and_a_drift() {
        let clean = sine(1.0, 0.01, 10.0, 1.0);
        let mut dirty = clean.clone();
        for (k, a) in dirty.accel.iter_mut().enumerate() {
            a[0] += 0.02 + 0.003 * k as f64 * 0.01;
        }
        let v_end = |r: &Record| r.velocity().last().unwrap()[0];
        assert!(v_end(&dirty).abs() > 0.3, "the drift builds a velocity");
        let fixed = dirty.baseline_corrected(2).unwrap();
        // The clean record ends at rest (whole cycles); so does the corrected one, and its peak
        // velocity is the clean one's (closed form 2A/ω = 1/π) within a few per cent.
        assert!(v_end(&fixed).abs() < 0.01, "{}", v_end(&fixed));
        let pgv = fixed.velocity().iter().map(|v| v[0].abs()).fold(0.0, f64::max);
        assert!((pgv - 1.0 / PI).abs() < 0.03 / PI, "{pgv}");
        // Order 0 changes nothing; order 1 removes the offset alone.
        assert_eq!(dirty.baseline_corrected(0).unwrap().accel, dirty.accel);
        assert!(v_end(&dirty.baseline_corrected(1).unwrap()).abs() < v_end(&dirty).abs() / 5.0);
        assert!(dirty.baseline_corrected(4).is_err());
    }

    #[test]
    fn downsampling_filters_what_would_alias() {
        // 100 Hz sampled at 1 kHz, resampled to 150 Hz (Nyquist 75 Hz): plain decimation would
        // fold it onto 50 Hz at full amplitude; the filtered record keeps < 1 % of it.
        let high = sine(100.0, 1e-3, 4.0, 1.0);
        let naive: Vec<f64> = (0..600).map(|k| high.at(k as f64 / 150.0)[0]).collect();
        let naive_rms = (naive.iter().map(|x| x * x).sum::<f64>() / naive.len() as f64).sqrt();
        assert!(naive_rms > 0.5, "decimation aliases: {naive_rms}");
        let down = high.resampled(1.0 / 150.0).unwrap();
        assert!(rms_x(&down, 0.5, 3.5) < 0.01, "{}", rms_x(&down, 0.5, 3.5));
        // A 5 Hz sine passes unchanged (away from the ends).
        let low = sine(5.0, 1e-3, 4.0, 1.0).resampled(1.0 / 150.0).unwrap();
        assert!((rms_x(&low, 0.5, 3.5) - 0.5f64.sqrt()).abs() < 0.01, "{}", rms_x(&low, 0.5, 3.5));
        assert!((low.dt - 1.0 / 150.0).abs() < 1e-15);
        assert!((low.duration() - 4.0).abs() <= low.dt);
    }

    #[test]
    fn upsampling_interpolates() {
        let r = sine(1.0, 0.01, 2.0, 1.0);
        let up = r.resampled(0.001).unwrap();
        assert_eq!(up.accel.len(), 2001);
        for k in (0..2001).step_by(10) {
            assert!((up.accel[k][0] - r.accel[k / 10][0]).abs() < 1e-12);
        }
    }

    #[test]
    fn a_scaled_record_is_the_same_case_by_name_and_scale_alone() {
        let r = sine(1.0, 0.01, 2.0, 3.0);
        let m = r.measures();
        let a = ScaledRecord::of(&r, 0.5, &m);
        // Other measures (another rock's resampling) do not matter; another scale or record does.
        assert!(a.same_as(&ScaledRecord { pga_g: 9.0, ..a.clone() }));
        assert!(!a.same_as(&ScaledRecord::of(&r, 0.5 + 1e-12, &m)));
        assert!(!a.same_as(&ScaledRecord { record: "other".into(), ..a.clone() }));
    }
}
