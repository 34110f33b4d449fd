//! Ground velocity as strong-motion processing computes it, and the PGV read from it.
//!
//! The velocity integrated from an acceleration record as given ([`Record::velocity`]) drifts:
//! an offset of 10⁻³ g left in a 40 s record adds 0.4 m/s to it, and the long periods an
//! accelerometer (a shake table's too) cannot resolve add more. Strong-motion practice corrects
//! the baseline and removes those periods with an acausal high-pass filter before integrating
//! (Boore & Bommer 2005). [`Record::processed`] does, for each component:
//!
//! 1. **Baseline**: the mean of the acceleration over the record is removed, so that
//!    ∫a dt = 0: the ground is at rest at both ends of the record (v(T) = v(0) = 0), the
//!    simplest baseline correction of Boore & Bommer (2005).
//! 2. **Pads**: ⌈1.5 n / (f_c dt)⌉ zeros before and after the record — the total pad length
//!    Converse & Brady (1992) give for an acausal Butterworth filter of order n and corner f_c
//!    (Boore 2005; gmprocess splits it between the ends), here at each end — so the filter's
//!    two-sided response has room and nothing wraps around the FFT.
//! 3. **High-pass**: the spectrum of the padded record (FFT) is multiplied by
//!
//!    ```text
//!    |H(f)|² = 1 / (1 + (f_c/f)^(2n)),    0 at f = 0,
//!    ```
//!
//!    the squared magnitude of the n-th order Butterworth high-pass: what passing that filter
//!    forward and then backward in time does (zero phase, "acausal"): 1/2 at the corner,
//!    ≈ (f/f_c)^(2n) well below it, ≈ 1 − (f_c/f)^(2n) well above it.
//! 4. **Velocity**: the trapezoid rule from v = 0 at the first pad sample, over the padded
//!    record: the pads are kept, as Boore (2005) advises, since the acausal filter's response
//!    reaches into them.
//!
//! PGV is the peak of the horizontal resultant of that velocity over the padded record
//! ([`Processed::pgv`]).
//!
//! # The corner and the order
//!
//! PEER and the USGS choose each record's high-pass corner from the signal-to-noise ratio of its
//! Fourier spectrum against its pre-event noise. A record here carries no noise window, so the
//! corner is a stated constant: [`Processing::default`] takes f_c = 0.08 Hz and n = 5, the
//! constant corner and the high-pass of the USGS processing software gmprocess's default
//! configuration (Butterworth of order 5 in two passes, 0.08 Hz when the corners are not picked
//! from the noise). Periods longer than 1/f_c = 12.5 s are removed; one sine cycle of
//! acceleration lasting T loses about T f_c (π/2n)/sin(π/2n) of its peak (it leaves the ground displaced,
//! which a high-pass cannot keep). Give another corner with [`Processing`].
//!
//! # Why this is written here
//!
//! The filter is applied in the frequency domain with `realfft`, the FFT the crate already uses
//! to resample records, where the zero-phase Butterworth is its closed-form magnitude: no IIR
//! design (bilinear transform, second-order sections, the forward–backward pass and its edge
//! transients) is needed, and the response is the analogue one at every frequency, not warped
//! near the Nyquist frequency — gmprocess filters in the frequency domain by default too. It is
//! checked against closed forms: the response at the corner is 1/2 (1/√2 per pass), a constant
//! offset is removed exactly, a cosine integrates to its velocity amplitude A/ω, a short pulse
//! loses the fraction above.

use super::Record;
use crate::{Error, Result};
use realfft::RealFftPlanner;

/// The parameters of the processing (see the module doc).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Processing {
    /// High-pass corner f_c (Hz). Default 0.08 Hz.
    pub corner_hz: f64,
    /// Order n of the Butterworth high-pass (per pass; the zero-phase response is its square).
    /// Default 5.
    pub order: u32,
}

impl Default for Processing {
    fn default() -> Processing {
        Processing { corner_hz: 0.08, order: 5 }
    }
}

impl Processing {
    /// Refuses a corner that is not positive and finite and an order outside 1–10.
    pub fn check(&self) -> Result<()> {
        if !(self.corner_hz > 0.0 && self.corner_hz.is_finite()) {
            return Err(Error::parameter("corner_hz", self.corner_hz, "a positive high-pass corner (Hz)"));
        }
        if !(1..=10).contains(&self.order) {
            return Err(Error::parameter("order", self.order, "a Butterworth order from 1 to 10"));
        }
        Ok(())
    }

    /// Zeros added before and after a record sampled at `dt` (s): ⌈1.5 n / (f_c dt)⌉.
    pub fn pad_samples(&self, dt: f64) -> usize {
        // Rounding noise of dt (an interval read from printed times) does not add a sample.
        (1.5 * self.order as f64 / (self.corner_hz * dt) * (1.0 - 1e-12)).ceil() as usize
    }

    /// The zero-phase response |H(f)|² = 1/(1 + (f_c/f)^(2n)) at frequency `f` (Hz); 0 at f = 0.
    pub fn response(&self, f: f64) -> f64 {
        if f <= 0.0 {
            return 0.0;
        }
        1.0 / (1.0 + (self.corner_hz / f).powi(2 * self.order as i32))
    }
}

/// A processed record: the filtered acceleration and its velocity over the padded record.
#[derive(Clone, Debug, PartialEq)]
pub struct Processed {
    /// Sampling interval (s), the record's.
    pub dt: f64,
    /// Zeros added before the record: sample k of the record is sample `pad + k` here.
    pub pad: usize,
    /// Baseline-corrected, high-passed acceleration (m/s²), `[x, y, z]`, over the padded record.
    pub accel: Vec<[f64; 3]>,
    /// Ground velocity (m/s), the trapezoid rule from 0 at the first sample of `accel`.
    pub velocity: Vec<[f64; 3]>,
}

impl Processed {
    /// Peak horizontal ground velocity (m/s): max over the padded record of |(v_x, v_y)|.
    pub fn pgv(&self) -> f64 {
        self.velocity.iter().map(|v| v[0].hypot(v[1])).fold(0.0, f64::max)
    }
}

impl Record {
    /// The record processed as the module doc says, with parameters `p` (checked).
    pub fn processed(&self, p: &Processing) -> Result<Processed> {
        p.check()?;
        Ok(self.processed_unchecked(p))
    }

    /// [`Record::processed`] with parameters known to be valid.
    pub(super) fn processed_unchecked(&self, p: &Processing) -> Processed {
        let n = self.accel.len();
        let pad = p.pad_samples(self.dt);
        let len = n + 2 * pad;
        let mut planner = RealFftPlanner::<f64>::new();
        let (fwd, inv) = (planner.plan_fft_forward(len), planner.plan_fft_inverse(len));
        let df = 1.0 / (len as f64 * self.dt);
        let mut accel = vec![[0.0; 3]; len];
        for c in 0..3 {
            let mean = self.accel.iter().map(|a| a[c]).sum::<f64>() / n as f64;
            let mut x = vec![0.0; len];
            for (xi, a) in x[pad..pad + n].iter_mut().zip(&self.accel) {
                *xi = a[c] - mean;
            }
            if x.iter().all(|v| *v == 0.0) {
                continue;
            }
            let mut spec = fwd.make_output_vec();
            fwd.process(&mut x, &mut spec).expect("lengths from the plan");
            for (k, s) in spec.iter_mut().enumerate() {
                *s *= p.response(k as f64 * df) / len as f64;
            }
            // The inverse of a real signal's spectrum: the DC and (even length) Nyquist bins are real.
            spec[0].im = 0.0;
            if len % 2 == 0 {
                if let Some(last) = spec.last_mut() {
                    last.im = 0.0;
                }
            }
            let mut out = inv.make_output_vec();
            inv.process(&mut spec, &mut out).expect("lengths from the plan");
            for (a, y) in accel.iter_mut().zip(&out) {
                a[c] = *y;
            }
        }
        let velocity = super::trapezoid(self.dt, &accel);
        Processed { dt: self.dt, pad, accel, velocity }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    /// `a(t) = amp·cos(2π f t) + offset` along x for `duration` s at `dt`: `duration/dt` samples,
    /// so that whole cycles sum to zero.
    fn cosine(f: f64, amp: f64, offset: f64, dt: f64, duration: f64) -> Record {
        let n = (duration / dt).round() as usize;
        let accel = (0..n).map(|k| [amp * (2.0 * PI * f * k as f64 * dt).cos() + offset, 0.0, 0.0]).collect();
        Record::new("cosine", dt, accel).unwrap()
    }

    /// Amplitude of the processed x acceleration over the record's middle half.
    fn middle_amplitude(r: &Record, p: &Processing) -> f64 {
        let out = r.processed(p).unwrap();
        let n = r.accel.len();
        out.accel[out.pad + n / 4..out.pad + 3 * n / 4].iter().map(|a| a[0].abs()).fold(0.0, f64::max)
    }

    #[test]
    fn the_zero_phase_response_is_the_butterworth_squared() {
        // Corner 1 Hz, order 5: a cosine of 200 cycles at f comes out with amplitude |H(f)|².
        let p = Processing { corner_hz: 1.0, order: 5 };
        let at = |f: f64| middle_amplitude(&cosine(f, 1.0, 0.0, 0.01, 200.0 / f), &p);
        // At the corner: (1/√2)² = 1/2.
        assert!((at(1.0) - 0.5).abs() < 2e-3, "{}", at(1.0));
        // An octave above: 1/(1 + 2⁻¹⁰); an octave below: 1/(1 + 2¹⁰).
        assert!((at(2.0) - 1.0 / (1.0 + 2f64.powi(-10))).abs() < 2e-3, "{}", at(2.0));
        assert!((at(0.5) - 1.0 / (1.0 + 2f64.powi(10))).abs() < 5e-4, "{}", at(0.5));
        assert_eq!(p.response(1.0), 0.5);
        assert_eq!(p.response(0.0), 0.0);
    }

    #[test]
    fn a_cosine_integrates_to_its_velocity_amplitude_and_an_offset_is_removed() {
        // a = A cos ωt + c: v = (A/ω) sin ωt once the offset is gone, amplitude A/ω. Raw
        // integration keeps c·t: 0.05 m/s² over 200 s is 10 m/s. The middle half of the record is
        // 50 s from its ends, where the filter's response to the abrupt start has died out
        // (its envelope decays as exp(−2π f_c sin(π/2n) t), e⁻⁸ there).
        let (amp, f, c) = (2.0, 1.5, 0.05);
        let (w, p) = (2.0 * PI * f, Processing::default());
        let r = cosine(f, amp, c, 0.005, 200.0);
        let out = r.processed(&p).unwrap();
        let n = r.accel.len();
        let middle = out.velocity[out.pad + n / 4..out.pad + 3 * n / 4].iter().map(|v| v[0].abs()).fold(0.0, f64::max);
        // The trapezoid rule is exact to (ω dt)²/12 = 1.9·10⁻⁴.
        assert!((middle * w / amp - 1.0).abs() < 5e-4, "{middle} vs {}", amp / w);
        // Over the whole record the abrupt start adds at most what the high-pass takes from the
        // velocity's steps at the ends, (A/ω²) · 2 f_c (π/2n)/sin(π/2n) (1.7 % here), and the
        // trapezoid from the last zero of the pad to a(0) = A, A dt/2.
        let edge = amp / (w * w) * 2.0 * p.corner_hz * (PI / 10.0) / (PI / 10.0).sin() + amp * 0.005 / 2.0;
        assert!(out.pgv() >= middle && out.pgv() <= amp / w + edge, "{} vs {} + {edge}", out.pgv(), amp / w);
        let raw = r.velocity().iter().map(|v| v[0].abs()).fold(0.0, f64::max);
        assert!(raw > 9.9, "{raw}");
        // A constant alone leaves nothing.
        let flat = Record::new("flat", 0.01, vec![[0.3, -0.2, 0.1]; 500]).unwrap();
        let out = flat.processed(&p).unwrap();
        assert!(out.velocity.iter().flatten().all(|v| v.abs() < 1e-12));
    }

    #[test]
    fn a_short_pulse_loses_its_displacement_to_the_high_pass() {
        // One sine cycle a = A sin ωt, T = 2π/ω: v = (A/ω)(1 − cos ωt), peak 2A/ω, area (A/ω)T.
        // The high-pass subtracts the low-passed velocity, ≈ area × ∫(1 − |H|²) df over ±f
        // = area · 2 f_c (π/2n)/sin(π/2n) at the pulse: PGV ≈ 2A/ω · (1 − T f_c (π/2n)/sin(π/2n)).
        let p = Processing::default();
        for t in [0.5, 1.0, 2.0] {
            let n = 2000;
            let dt = t / n as f64;
            let accel = (0..=4 * n)
                .map(|k| [if k <= n { (2.0 * PI * k as f64 / n as f64).sin() } else { 0.0 }, 0.0, 0.0])
                .collect();
            let r = Record::new("pulse", dt, accel).unwrap();
            let pgv = r.processed(&p).unwrap().pgv();
            let w = 2.0 * PI / t;
            let kappa = (PI / 10.0) / (PI / 10.0).sin();
            let expected = 2.0 / w * (1.0 - t * p.corner_hz * kappa);
            assert!((pgv / expected - 1.0).abs() < 3e-3, "T = {t}: {pgv} vs {expected}");
        }
    }

    #[test]
    fn processing_is_linear_and_of_the_horizontal_resultant() {
        let r = cosine(1.0, 1.0, 0.0, 0.01, 30.0);
        let p = Processing::default();
        let one = r.processed(&p).unwrap().pgv();
        assert!((r.scaled(-3.0).processed(&p).unwrap().pgv() / one - 3.0).abs() < 1e-9);
        // Turning the horizontal plane does not change the resultant's peak.
        let turned = r.rotated(0.7).processed(&p).unwrap().pgv();
        assert!((turned / one - 1.0).abs() < 1e-9);
    }

    #[test]
    fn bad_parameters_are_refused() {
        let r = cosine(1.0, 1.0, 0.0, 0.01, 2.0);
        for p in [
            Processing { corner_hz: 0.0, order: 5 },
            Processing { corner_hz: f64::NAN, order: 5 },
            Processing { corner_hz: 0.1, order: 0 },
            Processing { corner_hz: 0.1, order: 11 },
        ] {
            assert!(r.processed(&p).is_err(), "{p:?}");
        }
    }
}
