//! What a person reads of the two-tolerance hand experimenter ([`crate::study::hand`]): the
//! pebble columns (most likely pair, its probability, the distribution), the per-pebble JSON,
//! the model-against-Table-2 table with z-scores and its plot.

use crate::plot::{colors, Axis, Chart, Figure, Mark};
use crate::study::{CountDistribution, HandExperimenter, SampleFit, Study};
use plotters::style::colors::BLACK;
use serde::Serialize;

/// The hand columns of the pebble CSV with the two-tolerance experimenter: the most likely pair
/// (`hand_S`, `hand_U`, `hand_H` = S + U − 2), its probability, E(S), E(U), and every pair with
/// P ≥ 10⁻⁴ as `S:U:P` separated by spaces, most likely first.
pub const PAIR_COLUMNS: [&str; 7] = ["hand_S", "hand_U", "hand_H", "hand_p", "hand_E_S", "hand_E_U", "hand_pairs"];

/// Smallest probability of a pair listed in `hand_pairs`.
pub const LISTED_PAIR: f64 = 1e-4;

/// The [`PAIR_COLUMNS`] cells of one pebble's distribution.
pub fn pair_cells(d: &CountDistribution) -> Vec<String> {
    let best = d.most_likely();
    let pairs: Vec<String> = d
        .pairs()
        .iter()
        .filter(|p| p.p >= LISTED_PAIR)
        .map(|p| format!("{}:{}:{:.4}", p.stable, p.unstable, p.p))
        .collect();
    vec![
        best.stable.to_string(),
        best.unstable.to_string(),
        best.saddle.to_string(),
        format!("{:.4}", best.p),
        format!("{:.4}", d.stable_moments()[0]),
        format!("{:.4}", d.unstable_moments()[0]),
        pairs.join(" "),
    ]
}

/// One pebble of the JSON of the distributions.
#[derive(Serialize)]
struct PebbleHand<'a> {
    id: &'a str,
    sample: &'a str,
    file: &'a str,
    most_likely: crate::study::HandPair,
    distribution: CountDistribution,
}

/// The JSON of a study's hand experimenter: `{"experimenter": …, "pebbles": [{id, sample, file,
/// most_likely: {stable, unstable, saddle, p}, distribution: {stable: [{count, p}], unstable:
/// […]}}]}`, the analysed pebbles only; the one-ν experimenter (certain counts) without a
/// two-tolerance one.
pub fn hand_json(study: &Study) -> crate::Result<String> {
    let exp = study.hand.unwrap_or_else(|| HandExperimenter::one_nu(study.nu));
    let pebbles: Vec<PebbleHand> = study
        .pebbles
        .iter()
        .filter_map(|p| {
            let d = study.distribution(p.result.as_ref().ok()?);
            Some(PebbleHand {
                id: &p.id,
                sample: &p.sample,
                file: &p.file,
                most_likely: d.most_likely(),
                distribution: d,
            })
        })
        .collect();
    serde_json::to_string_pretty(&serde_json::json!({ "experimenter": exp, "pebbles": pebbles }))
        .map_err(|e| crate::Error::write(crate::error::MEMORY, Box::new(e)))
}

/// Header of [`write_sample_fits_csv`].
pub const SAMPLE_FIT_COLUMNS: [&str; 18] = [
    "sample",
    "n_model",
    "hand_E_S",
    "hand_E_U",
    "hand_sd_S",
    "hand_sd_U",
    "model_E_S",
    "model_E_U",
    "model_sd_S",
    "model_sd_U",
    "z_E_S",
    "z_E_U",
    "z_sd_S",
    "z_sd_U",
    "chi2",
    "se_hand_E_S",
    "se_hand_E_U",
    "se_hand_sd_S",
];

/// One row per sample: Table 2's hand columns, the model's, the z-scores and χ² (σ: sample
/// standard deviations, n − 1).
pub fn write_sample_fits_csv<W: std::io::Write>(rows: &[SampleFit], w: W) -> crate::Result<()> {
    (|| -> std::result::Result<_, crate::error::BoxError> {
        let mut out = csv::Writer::from_writer(w);
        out.write_record(SAMPLE_FIT_COLUMNS)?;
        for r in rows {
            let se = crate::study::HandSample::standard_errors_of(&r.hand, 50);
            let mut row = vec![r.id.clone(), r.model.n.to_string()];
            row.extend(r.hand.iter().chain(&r.model.as_array()).map(|x| format!("{x:.4}")));
            row.extend(r.z.iter().map(|x| format!("{x:.3}")));
            row.push(format!("{:.3}", r.chi2));
            row.extend(se[..3].iter().map(|x| format!("{x:.4}")));
            out.write_record(row)?;
        }
        out.flush()?;
        Ok(())
    })()
    .map_err(|e| crate::Error::write(crate::error::MEMORY, e))
}

/// Model against Table 2 per sample: four panels (E(S), E(U), σ(S), σ(U)) over the samples,
/// the hand values as dots with ±1 standard error (σ/√n, σ/√(2(n − 1)), n = `n_hand`), each
/// model of `models` (label, rows in the same sample order) as rings or squares of its colour.
pub fn hand_vs_table2(title: &str, n_hand: usize, models: &[(String, &[SampleFit])]) -> Figure {
    let Some((_, first)) = models.first() else { return Figure::new(title, 2, vec![]) };
    let names: Vec<String> = first.iter().map(|r| r.id.clone()).collect();
    let colours = [colors::VERMILLION, colors::BLUE, colors::GREEN];
    let panel = |k: usize| {
        let hand: Vec<(f64, f64)> = first.iter().enumerate().map(|(i, r)| (i as f64, r.hand[k])).collect();
        let se: Vec<(f64, f64, f64)> = first
            .iter()
            .enumerate()
            .map(|(i, r)| {
                let e = crate::study::HandSample::standard_errors_of(&r.hand, n_hand)[k];
                (i as f64, r.hand[k] - e, r.hand[k] + e)
            })
            .collect();
        let values = models.iter().flat_map(|(_, rows)| rows.iter().map(move |r| r.model.as_array()[k]));
        let top = values.chain(se.iter().map(|b| b.2)).fold(0.0f64, f64::max) * 1.1 + 0.1;
        let name = ["E(S)", "E(U)", "σ(S)", "σ(U)"][k];
        let mut c = Chart::new(Axis::categories("sample", names.clone()), Axis::linear(name, 0.0, top))
            .title(name)
            .y_bars(&se, BLACK)
            .dots(&hand, BLACK);
        for (j, (_, rows)) in models.iter().enumerate() {
            let pts: Vec<(f64, f64)> =
                rows.iter().enumerate().map(|(i, r)| (i as f64, r.model.as_array()[k])).collect();
            c = c.rings(&pts, colours[j % colours.len()]);
        }
        c
    };
    let mut f = Figure::new(title, 2, (0..4).map(panel).collect())
        .legend(Mark::Dot(BLACK), "Table 2, hand (±1 standard error)");
    for (j, (label, _)) in models.iter().enumerate() {
        f = f.legend(Mark::Ring(colours[j % colours.len()]), label.clone());
    }
    f
}
