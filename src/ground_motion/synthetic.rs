//! Synthetic ground motions: the pulses of the rigid-block literature and filtered noise with an
//! envelope, the classical stand-in for recorded accelerograms.
//!
//! * [`one_sine_pulse`]: Makris & Roussos (2000)'s type-A pulse, one full cycle of
//!   a(t) = a_p sin(ω_p t), 0 ≤ t ≤ T_p = 2π/ω_p. Closed forms: PGA = a_p,
//!   v(t) = (a_p/ω_p)(1 − cos ω_p t), PGV = 2 a_p/ω_p = a_p T_p/π, PGV/PGA = T_p/π; the ground
//!   ends at rest, displaced by a_p T_p²/(2π). The pulses ([`sine_cycles`]) carry that PGV as
//!   known ([`Record::with_known_pgv`]): the processed one would lose the displacement to the
//!   high-pass (see [`super::processing`]).
//! * [`filtered_noise`]: Gaussian white noise through the Kanai–Tajimi soil filter (natural
//!   period T_g, damping ζ_g) and the Clough–Penzien high-pass (corner ω_f = ω_g/10, ζ_f = ζ_g),
//!   which removes the unphysical low-frequency content of the Kanai–Tajimi spectrum, times the
//!   envelope (t/t_p)² e^(2(1 − t/t_p)) peaking at t_p = duration/4, then baseline-corrected
//!   (order 1). Its predominant period is near T_g; scale it with [`Record::scaled_to_pga`].

use super::Record;
use crate::rng::item_rng;
use crate::GRAVITY as G;
use crate::{Error, Result};
use rand_distr::{Distribution, StandardNormal};
use std::f64::consts::PI;

/// One full sine cycle of acceleration of peak `ap_g` (g) and period `tp` (s), along x, sampled
/// at `dt` (s).
pub fn one_sine_pulse(ap_g: f64, tp: f64, dt: f64) -> Result<Record> {
    sine_cycles(ap_g, tp, 1.0, dt)
}

/// `cycles` sine cycles a(t) = a_p sin(2π t / T_p), 0 ≤ t ≤ cycles·T_p, of peak `ap_g` (g) and
/// period `tp` (s), along x, sampled at about `dt` (s: the nearest interval that divides a
/// period into a whole number of samples).
pub fn sine_cycles(ap_g: f64, tp: f64, cycles: f64, dt: f64) -> Result<Record> {
    if !(tp > 0.0 && tp.is_finite() && dt > 0.0 && dt < tp) {
        return Err(Error::motion("sine pulse", format!("needs 0 < dt < T_p, got T_p = {tp} s, dt = {dt} s")));
    }
    if !(cycles > 0.0 && cycles.is_finite() && ap_g.is_finite()) {
        return Err(Error::motion("sine pulse", format!("needs a finite peak and cycles > 0, got {ap_g} g, {cycles}")));
    }
    let n = (tp / dt).round() as usize;
    let dt = tp / n as f64;
    let samples = ((cycles * n as f64).round() as usize).max(1);
    let accel = (0..=samples).map(|k| [ap_g * G * (2.0 * PI * k as f64 / n as f64).sin(), 0.0, 0.0]).collect();
    // Four decimals of a second, and none where they are zeros (T_p = 2 s, 0.2111 s).
    let t = (tp * 1e4).round() / 1e4;
    let name = if cycles == 1.0 {
        format!("one-sine pulse a_p = {ap_g} g, T_p = {t} s")
    } else {
        format!("{cycles} sine cycles a_p = {ap_g} g, T_p = {t} s")
    };
    // v = (a_p/ω)(1 − cos ωt) over the sampled cycles c: its peak 2 a_p/ω from half a cycle on.
    let (amp, c) = ((ap_g * G).abs(), samples as f64 / n as f64);
    let pgv = amp * tp / (2.0 * PI) * if c >= 0.5 { 2.0 } else { 1.0 - (2.0 * PI * c).cos() };
    let record = Record::new(name, dt, accel)?;
    if pgv > 0.0 {
        record.with_known_pgv(pgv)
    } else {
        Ok(record)
    }
}

/// The parameters of [`filtered_noise`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Noise {
    /// Duration (s). Default 20 s.
    pub duration: f64,
    /// Predominant period T_g = 2π/ω_g of the Kanai–Tajimi filter (s). Default 0.4 s (firm soil).
    pub period: f64,
    /// Damping ζ_g of the filters. Default 0.6.
    pub damping: f64,
    /// Sampling interval (s). Default 0.005 s (200 Hz).
    pub dt: f64,
    /// Number of components: 1 (x), 2 (x, y) or 3 (x, y and a vertical z at 2/3 of the
    /// horizontal amplitude, a common rule of thumb). Default 1.
    pub components: usize,
}

impl Default for Noise {
    fn default() -> Noise {
        Noise { duration: 20.0, period: 0.4, damping: 0.6, dt: 0.005, components: 1 }
    }
}

/// Filtered noise (see the module doc), peak horizontal acceleration scaled to `pga_g` (g),
/// drawn from stream `seed` ([`item_rng`]).
pub fn filtered_noise(noise: &Noise, pga_g: f64, seed: u64) -> Result<Record> {
    let Noise { duration, period, damping, dt, components } = *noise;
    if !(duration > 0.0 && period > 0.0 && damping > 0.0 && dt > 0.0 && duration > 10.0 * dt) {
        return Err(Error::motion(
            "filtered noise",
            format!("needs positive duration ≫ dt, period and damping, got {noise:?}"),
        ));
    }
    if period < 4.0 * dt {
        return Err(Error::motion(
            "filtered noise",
            format!("a predominant period of {period} s needs dt ≤ {} s", period / 4.0),
        ));
    }
    if !(1..=3).contains(&components) {
        return Err(Error::parameter("components", components, "1 to 3"));
    }
    let n = (duration / dt).round() as usize + 1;
    let mut accel = vec![[0.0; 3]; n];
    for c in 0..components {
        let mut rng = item_rng(seed, c as u64);
        let series = kanai_tajimi_clough_penzien(n, dt, 2.0 * PI / period, damping, &mut rng);
        let gain = if c == 2 { 2.0 / 3.0 } else { 1.0 };
        for (k, (a, x)) in accel.iter_mut().zip(series).enumerate() {
            let u = k as f64 * dt / (duration / 4.0);
            a[c] = gain * x * u * u * (2.0 * (1.0 - u)).exp();
        }
    }
    let name = format!("filtered noise T_g = {period} s, {duration} s, seed {seed}");
    let record = Record::new(name, dt, accel)?.baseline_corrected(1)?;
    Ok(record.scaled_to_pga(pga_g))
}

/// The two filters driven by unit white noise, integrated with 10 substeps of semi-implicit
/// Euler per sample; returns the ground acceleration of the Clough–Penzien model at each sample.
fn kanai_tajimi_clough_penzien(n: usize, dt: f64, wg: f64, zg: f64, rng: &mut crate::rng::Stream) -> Vec<f64> {
    let (wf, zf) = (0.1 * wg, zg);
    let sub = 10;
    let h = dt / sub as f64;
    let (mut x, mut v, mut y, mut w) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
    let mut out = Vec::with_capacity(n);
    for _ in 0..n {
        let mut a = 0.0;
        for _ in 0..sub {
            let noise: f64 = StandardNormal.sample(rng);
            let u = noise / h.sqrt();
            // Kanai–Tajimi: ẍ + 2ζ_g ω_g ẋ + ω_g² x = −u; its absolute acceleration a_KT.
            v += (-u - 2.0 * zg * wg * v - wg * wg * x) * h;
            x += v * h;
            let a_kt = -(2.0 * zg * wg * v + wg * wg * x);
            // Clough–Penzien: ÿ + 2ζ_f ω_f ẏ + ω_f² y = a_KT; the ground acceleration is ÿ, whose
            // transfer function ω²/(ω_f² − ω² + 2iζ_f ω_f ω) is a high-pass at ω_f.
            let yy = a_kt - 2.0 * zf * wf * w - wf * wf * y;
            w += yy * h;
            y += w * h;
            a = yy;
        }
        out.push(a);
    }
    out
}

/// A family of [`filtered_noise`] records: `noise` at each predominant period of `periods` ×
/// each stream of `seeds` (the seeds inner), every one scaled to PGA `pga_g` (g) and named
/// `name(period, seed)`.
pub fn noise_family(
    noise: &Noise,
    pga_g: f64,
    periods: &[f64],
    seeds: &[u64],
    name: impl Fn(f64, u64) -> String,
) -> Result<Vec<Record>> {
    let mut records = Vec::new();
    for &period in periods {
        for &seed in seeds {
            let mut r = filtered_noise(&Noise { period, ..*noise }, pga_g, seed)?;
            r.name = name(period, seed);
            records.push(r);
        }
    }
    Ok(records)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_sine_pulse_has_closed_form_peaks() {
        let (ap, tp) = (0.4, 0.5);
        let r = one_sine_pulse(ap, tp, 1e-4).unwrap();
        let m = r.measures();
        assert!((m.pga_g - ap).abs() < 1e-6, "{m:?}");
        let pgv = ap * G * tp / PI;
        assert!((m.pgv_m_s - pgv).abs() < 1e-12 * pgv, "{} vs {pgv}", m.pgv_m_s);
        assert_eq!(m.pgv_source, crate::ground_motion::PgvSource::Given);
        assert!((m.pgv_over_pga_s - tp / PI).abs() < 1e-6);
        // The known PGV is that of the samples: their trapezoid velocity peaks there too.
        let raw = r.velocity().iter().map(|v| v[0].abs()).fold(0.0, f64::max);
        assert!((raw - pgv).abs() < 1e-6 * pgv, "{raw} vs {pgv}");
        // A quarter cycle: v peaks at its end, (a_p/ω)(1 − cos π/2) = a_p/ω.
        let quarter = sine_cycles(ap, tp, 0.25, 1e-4).unwrap();
        let raw = quarter.velocity().iter().map(|v| v[0].abs()).fold(0.0, f64::max);
        assert!((quarter.measures().pgv_m_s - raw).abs() < 1e-6 * raw, "{:?} vs {raw}", quarter.measures());
        assert!(one_sine_pulse(ap, tp, 0.6).is_err());
    }

    /// Frequencies (Hz) and periodogram of the x component.
    fn periodogram(r: &Record) -> (Vec<f64>, Vec<f64>) {
        let mut x: Vec<f64> = r.accel.iter().map(|a| a[0]).collect();
        let n = x.len();
        let fft = realfft::RealFftPlanner::<f64>::new().plan_fft_forward(n);
        let mut spec = fft.make_output_vec();
        fft.process(&mut x, &mut spec).unwrap();
        let df = 1.0 / (n as f64 * r.dt);
        ((0..spec.len()).map(|k| k as f64 * df).collect(), spec.iter().map(|c| c.norm_sqr()).collect())
    }

    /// The frequency below which half of the power lies (uniform grid).
    fn median_frequency(f: &[f64], p: &[f64]) -> f64 {
        let total: f64 = p.iter().sum();
        let mut acc = 0.0;
        for (fk, pk) in f.iter().zip(p) {
            acc += pk;
            if acc >= 0.5 * total {
                return *fk;
            }
        }
        f[f.len() - 1]
    }

    #[test]
    fn filtered_noise_is_reproducible_scaled_and_at_its_period() {
        let noise = Noise { duration: 40.0, ..Noise::default() };
        let a = filtered_noise(&noise, 0.3, 7).unwrap();
        assert_eq!(a, filtered_noise(&noise, 0.3, 7).unwrap());
        assert_ne!(a, filtered_noise(&noise, 0.3, 8).unwrap());
        assert!((a.measures().pga_g - 0.3).abs() < 1e-12);
        // The baseline correction leaves the ground nearly at rest at the end (a linear
        // baseline does not force it; a uniform final velocity is harmless to a rock anyway).
        let v_end = a.velocity().last().unwrap()[0];
        assert!(v_end.abs() < 0.1 * a.measures().pgv_m_s, "{v_end} {:?}", a.measures());
        // The spectrum peaks where the Kanai–Tajimi × Clough–Penzien power spectrum does:
        // |H(ω)|² = (ω_g⁴ + 4ζ²ω_g²ω²)/((ω_g² − ω²)² + 4ζ²ω_g²ω²) · ω⁴/((ω_f² − ω²)² + 4ζ²ω_f²ω²).
        let (wg, z) = (2.0 * PI / noise.period, noise.damping);
        let wf = 0.1 * wg;
        let model = |w: f64| {
            let kt = (wg.powi(4) + 4.0 * z * z * wg * wg * w * w)
                / ((wg * wg - w * w).powi(2) + 4.0 * z * z * wg * wg * w * w);
            kt * w.powi(4) / ((wf * wf - w * w).powi(2) + 4.0 * z * z * wf * wf * w * w)
        };
        // Compare the median frequencies (half the power below) over 0.05–50 Hz: the peak of
        // so broad a spectrum is too flat to locate in one realisation.
        let grid: Vec<f64> = (5..5000).map(|k| k as f64 * 0.01).collect();
        let f_model = median_frequency(&grid, &grid.iter().map(|f| model(2.0 * PI * f)).collect::<Vec<_>>());
        let (f, p) = periodogram(&a);
        let band: Vec<usize> = (0..f.len()).filter(|&k| (0.05..50.0).contains(&f[k])).collect();
        let f_record = median_frequency(
            &band.iter().map(|&k| f[k]).collect::<Vec<_>>(),
            &band.iter().map(|&k| p[k]).collect::<Vec<_>>(),
        );
        assert!((f_record / f_model - 1.0).abs() < 0.15, "median {f_record} Hz, model {f_model} Hz");
        // A longer predominant period crosses zero less often, and gives a larger PGV/PGA.
        let slow = filtered_noise(&Noise { period: 1.2, ..noise }, 0.3, 7).unwrap();
        assert!(slow.measures().pgv_over_pga_s > 1.5 * a.measures().pgv_over_pga_s);
        let three = filtered_noise(&Noise { components: 3, ..noise }, 0.3, 7).unwrap();
        assert!(three.accel.iter().any(|x| x[1] != 0.0) && three.accel.iter().any(|x| x[2] != 0.0));
    }

    #[test]
    fn a_noise_family_has_every_period_and_seed_at_its_pga() {
        let noise = Noise { duration: 4.0, components: 2, ..Noise::default() };
        let family = noise_family(&noise, 0.3, &[0.2, 1.0], &[7, 8, 9], |t, s| format!("T{t}_s{s}")).unwrap();
        let names: Vec<&str> = family.iter().map(|r| r.name.as_str()).collect();
        assert_eq!(names, ["T0.2_s7", "T0.2_s8", "T0.2_s9", "T1_s7", "T1_s8", "T1_s9"]);
        for r in &family {
            assert!((r.measures().pga_g - 0.3).abs() < 1e-9, "{}: {:?}", r.name, r.measures());
            assert!(r.accel.iter().any(|a| a[1] != 0.0) && r.accel.iter().all(|a| a[2] == 0.0));
        }
        // Different streams are different records; the same period and stream, the same.
        assert_ne!(family[0].accel, family[1].accel);
        assert_eq!(family[4].accel, filtered_noise(&Noise { period: 1.0, ..noise }, 0.3, 8).unwrap().accel);
    }
}
