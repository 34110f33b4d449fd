//! Monte Carlo drops: many drops in parallel, reproducible per drop, sharded,
//! checkpointed, merged, and summarised against the static theory.
//!
//! * **Reproducibility.** Drop i of a run with seed s draws everything from its own generator,
//!   Xoshiro256++ seeded with SplitMix64(s, i) ([`item_rng`]); rapier is deterministic for a
//!   given binary and input. So the outcome of drop i does not depend on the thread count, the
//!   order of execution, or how the run is sharded: counts from any sharding merged with
//!   [`merge`] equal those of one big run.
//! * **Batches.** Drops run [`DEFAULT_BATCH`] stones per rapier world
//!   ([`crate::dynamics::drops::batch`]), which amortises rapier's per-step cost; each drop's
//!   outcome is bit-identical to the same drop alone in its world, for any batch size
//!   (`tests/batch.rs`).
//! * **Checkpoints.** A run appends every finished drop to a JSON-lines file (first line: the
//!   [`RunHeader`]) and flushes it, so an interrupted run loses no finished drop; resuming
//!   skips the indices already in the file.
//! * **Statistics.** Wilson score intervals (95 %) per facet and per flock; Pearson's χ² and the
//!   Kullback–Leibler divergence of the empirical distribution from the static one.

use crate::dynamics::certificate::{certificate, CertificateMode};
use crate::dynamics::drops::batch::simulate_batch;
use crate::dynamics::drops::launch::{launch, DropOutcome};
use crate::dynamics::drops::params::DropParams;
use crate::dynamics::drops::simulate::simulate;
use crate::dynamics::engine::params::REFERENCE_DT;
use crate::dynamics::engine::run::Certificate;
use crate::dynamics::stone::StaticModel;
use crate::dynamics::stone::Stone;
use crate::equilibria::Kind;
use crate::rng::item_rng;
use crate::stats::{chi_square, kl_divergence, wilson};
use crate::{Error, Result, Vec3};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::io::Write;
use std::path::Path;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;

/// Which drops a process runs: indices `index`, `index + count`, `index + 2 count`, …
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Shard {
    /// Which residue class of drop indices this process runs (0 ≤ index < count).
    pub index: u64,
    /// Number of shards the run is split into.
    pub count: u64,
}

impl Shard {
    /// The whole run.
    pub const ALL: Shard = Shard { index: 0, count: 1 };

    /// [`Shard::ALL`] (for serde defaults).
    pub fn all() -> Shard {
        Shard::ALL
    }

    /// Whether drop `i` belongs to this shard.
    pub fn holds(&self, i: u64) -> bool {
        self.count > 0 && i % self.count == self.index
    }

    /// Parse `i/n` (0 ≤ i < n).
    pub fn parse(s: &str) -> Result<Shard> {
        let bad = || Error::parameter("shard", format!("{s:?}"), "i/n with 0 ≤ i < n");
        let (i, n) = s.split_once('/').ok_or_else(bad)?;
        let (index, count) = (i.trim().parse().map_err(|_| bad())?, n.trim().parse().map_err(|_| bad())?);
        if count == 0 || index >= count {
            return Err(bad());
        }
        Ok(Shard { index, count })
    }

    /// The drop indices of this shard among `n`.
    pub fn indices(&self, n: u64) -> impl Iterator<Item = u64> + '_ {
        (self.index..n).step_by(self.count as usize)
    }
}

/// What identifies a run: every partial result of the same run has the same header.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RunHeader {
    /// Checkpoint format tag (`FORMAT`).
    pub format: String,
    /// The mesh file as given (for the report only).
    pub mesh: String,
    /// FNV-1a hash of the mesh's vertices and triangles after loading.
    pub mesh_fingerprint: String,
    /// Seed of the random streams of the drops.
    pub seed: u64,
    /// Number of drops in the run.
    pub drops: u64,
    /// Simulation parameters of the drops.
    pub params: DropParams,
    /// Whether and how the energy certificate may end a drop.
    pub certificate: CertificateMode,
    /// The preset and surface the parameters started from (for the report; `params` is what
    /// was run).
    #[serde(default)]
    pub preset: Option<String>,
    /// A declared centre of mass (mesh units), if the run used one instead of the solid's G.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub center_of_mass: Option<[f64; 3]>,
    /// The shard this file holds (the whole run: 0/1).
    #[serde(default = "Shard::all")]
    pub shard: Shard,
}

impl RunHeader {
    /// The header of a whole run (shard 0/1) of `drops` drops of `mesh` (named `mesh_name`) with
    /// `params`, started from `preset` on `surface`, as `rocking drop` and Python's `drop` write
    /// it; a declared centre of mass and a shard are set on the result.
    pub fn new(
        mesh_name: impl Into<String>,
        mesh: &crate::mesh::TriMesh,
        seed: u64,
        drops: u64,
        params: DropParams,
        certificate: CertificateMode,
        preset: (crate::dynamics::drops::params::Preset, crate::dynamics::surface::Surface),
    ) -> RunHeader {
        RunHeader {
            format: FORMAT.into(),
            mesh: mesh_name.into(),
            mesh_fingerprint: fingerprint(mesh),
            seed,
            drops,
            params,
            certificate,
            preset: Some(format!("{} on {}", preset.0, preset.1)),
            center_of_mass: None,
            shard: Shard::ALL,
        }
    }

    /// The fields (other than the shard) in which `other` differs from this header: empty when
    /// both belong to the same run.
    pub fn differences(&self, other: &RunHeader) -> Vec<String> {
        let mut d = Vec::new();
        let mut field = |name: &str, same: bool, a: String, b: String| {
            if !same {
                d.push(format!("{name} ({a} vs {b})"));
            }
        };
        field("format", self.format == other.format, self.format.clone(), other.format.clone());
        field(
            "mesh fingerprint",
            self.mesh_fingerprint == other.mesh_fingerprint,
            self.mesh_fingerprint.clone(),
            other.mesh_fingerprint.clone(),
        );
        field("seed", self.seed == other.seed, self.seed.to_string(), other.seed.to_string());
        field("drops", self.drops == other.drops, self.drops.to_string(), other.drops.to_string());
        field("parameters", self.params == other.params, params_text(&self.params), params_text(&other.params));
        field(
            "certificate",
            self.certificate == other.certificate,
            self.certificate.name().into(),
            other.certificate.name().into(),
        );
        field(
            "centre of mass",
            self.center_of_mass == other.center_of_mass,
            centre_text(self.center_of_mass),
            centre_text(other.center_of_mass),
        );
        d
    }
}

/// Parameters as a person compares them: their JSON.
fn params_text(p: &DropParams) -> String {
    serde_json::to_string(p).unwrap_or_default()
}

/// A centre of mass as given by `--center-of-mass`, or the homogeneous solid's.
fn centre_text(c: Option<[f64; 3]>) -> String {
    c.map_or("the homogeneous solid's G".into(), |[x, y, z]| format!("({x}, {y}, {z})"))
}

/// Header format tag of checkpoint files (2: launches with horizontal speed and Gaussian spin,
/// rolling resistance, outcomes by the quasi-static descent; 3: exact landings and sub-stepped
/// impacts under `flight = free`, now the default, and torsional friction on single contact
/// points only — a run of format 2 cannot be resumed or merged with the numerics of 3).
pub const FORMAT: &str = "rocking-drops/3";

/// FNV-1a over the bit patterns of the vertices and the triangle indices.
pub fn fingerprint(mesh: &crate::mesh::TriMesh) -> String {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    let mut eat = |x: u64| {
        for b in x.to_le_bytes() {
            h ^= b as u64;
            h = h.wrapping_mul(0x0100_0000_01b3);
        }
    };
    mesh.vertices.iter().flat_map(|p| p.coords.iter().copied().collect::<Vec<_>>()).for_each(|x| eat(x.to_bits()));
    mesh.triangles.iter().flatten().for_each(|&i| eat(i as u64));
    format!("{h:016x}")
}

/// Stones per rapier world in [`run_drops`] (`rocking drop --batch`), chosen from the batch-size sweep
/// of `results/drops_certificate/`: the gain over one world per drop levels off from about 16
/// stones per world (1.6–2.3× on throws) and falls beyond 64.
pub const DEFAULT_BATCH: usize = 32;

/// Run the drops of `shard` that are not in `done`, in parallel, [`DEFAULT_BATCH`] stones per
/// world, calling `on_done` (under a lock) as each finishes. Returns the new outcomes sorted by
/// index.
pub fn run_drops(
    stone: &Stone,
    header: &RunHeader,
    shard: Shard,
    done: &BTreeMap<u64, DropOutcome>,
    cert: &dyn Certificate,
    on_done: &Mutex<dyn FnMut(&DropOutcome) + Send + '_>,
) -> Vec<DropOutcome> {
    run_drops_batched(stone, header, shard, done, cert, DEFAULT_BATCH, on_done)
}

/// [`run_drops`] with `batch` stones per rapier world ([`crate::dynamics::drops::batch`]); 1: every drop
/// alone in its own world ([`simulate`]). Every drop's outcome is the same for any batch size
/// and thread count (`tests/batch.rs`). One world per thread takes the pending drops from a
/// shared queue.
pub fn run_drops_batched(
    stone: &Stone,
    header: &RunHeader,
    shard: Shard,
    done: &BTreeMap<u64, DropOutcome>,
    cert: &dyn Certificate,
    batch: usize,
    on_done: &Mutex<dyn FnMut(&DropOutcome) + Send + '_>,
) -> Vec<DropOutcome> {
    let todo: Vec<u64> = shard.indices(header.drops).filter(|i| !done.contains_key(i)).collect();
    let release = |i: u64| launch(&mut item_rng(header.seed, i), &header.params);
    let record = |o: &DropOutcome| (on_done.lock().expect("no panic while holding the lock"))(o);
    let mut out: Vec<DropOutcome> = if batch <= 1 {
        todo.par_iter()
            .map(|&i| {
                let o = simulate(stone, &header.params, &release(i), i, cert);
                record(&o);
                o
            })
            .collect()
    } else {
        // One world per thread, each taking the next pending drop as one of its stones comes to
        // rest: a world drains (fewer stones per step) once, at the end of the run, where
        // contiguous chunks drained at the end of every chunk.
        let next = AtomicUsize::new(0);
        let workers = rayon::current_num_threads().min(todo.len().div_ceil(batch)).max(1);
        let per_world: Vec<Vec<DropOutcome>> = (0..workers)
            .into_par_iter()
            .map(|_| {
                let mut outcomes = Vec::new();
                let mut queue =
                    std::iter::from_fn(|| todo.get(next.fetch_add(1, Ordering::Relaxed))).map(|&i| (i, release(i)));
                simulate_batch(stone, &header.params, cert, batch, &mut queue, &mut |o| {
                    record(&o);
                    outcomes.push(o);
                });
                outcomes
            })
            .collect();
        per_world.into_iter().flatten().collect()
    };
    out.sort_by_key(|o| o.index);
    out
}

/// What to say when a checkpoint's time step is not this run's: drops written before the default
/// step became the presets' longest stable one (1/120 s) ran at [`REFERENCE_DT`].
fn step_hint(checkpoint_dt: f64, run_dt: f64) -> String {
    if checkpoint_dt == run_dt {
        return String::new();
    }
    let reference = if checkpoint_dt == REFERENCE_DT {
        " (1/240 s: the reference step, the default before the drop presets took their longest stable step 1/120 s)"
    } else {
        ""
    };
    format!("; to resume it, run at its time step dt = {checkpoint_dt} s{reference}")
}

/// Append-only JSON-lines checkpoint of a run.
pub struct Checkpoint {
    file: std::io::BufWriter<std::fs::File>,
}

impl Checkpoint {
    /// Open `path` for a run with `header`. A new file gets the header; an existing file is
    /// read back (when `resume`) and must have the same header; without `resume` an existing
    /// file is an error (it would be overwritten).
    pub fn open(path: &Path, header: &RunHeader, resume: bool) -> Result<(Checkpoint, BTreeMap<u64, DropOutcome>)> {
        let io = |e: std::io::Error| Error::Io { path: path.into(), error: e };
        let mut done = BTreeMap::new();
        if path.exists() {
            if !resume {
                return Err(Error::parameter(
                    "resume",
                    "not set",
                    format!("set to continue the checkpoint {}, which exists (or remove that file)", path.display()),
                ));
            }
            let (h, outcomes) = read_partial(path)?;
            let mut differ = header.differences(&h);
            if h.shard != header.shard {
                differ.push(format!(
                    "shard ({}/{} vs {}/{})",
                    header.shard.index, header.shard.count, h.shard.index, h.shard.count
                ));
            }
            if !differ.is_empty() {
                return Err(Error::Usage(format!(
                    "{}: this checkpoint belongs to a different run; it differs in {}{}",
                    path.display(),
                    differ.join(", "),
                    step_hint(h.params.sim.numerics.dt, header.params.sim.numerics.dt)
                )));
            }
            done = outcomes;
            // Cut a line left half-written by an interrupted run before appending to the file.
            let bytes = std::fs::read(path).map_err(io)?;
            let complete = bytes.iter().rposition(|&b| b == b'\n').map_or(0, |i| i + 1);
            let file = std::fs::OpenOptions::new().write(true).open(path).map_err(io)?;
            file.set_len(complete as u64).map_err(io)?;
            let file = std::fs::OpenOptions::new().append(true).open(path).map_err(io)?;
            return Ok((Checkpoint { file: std::io::BufWriter::new(file) }, done));
        }
        let file = std::fs::File::create(path).map_err(io)?;
        let mut c = Checkpoint { file: std::io::BufWriter::new(file) };
        c.write_line(&serde_json::to_string(header).expect("header serialises")).map_err(io)?;
        Ok((c, done))
    }

    fn write_line(&mut self, line: &str) -> std::io::Result<()> {
        self.file.write_all(line.as_bytes())?;
        self.file.write_all(b"\n")?;
        self.file.flush()
    }

    /// Record one finished drop (flushed at once).
    pub fn record(&mut self, o: &DropOutcome) -> std::io::Result<()> {
        self.write_line(&serde_json::to_string(o).expect("outcome serialises"))
    }
}

/// Read a partial result (checkpoint file): its header and outcomes by index. A truncated last
/// line (an interrupted write) is ignored. Every line is checked against the header before it
/// counts: valid UTF-8 and JSON, a drop index below the run's drop count, in the file's shard, and
/// not seen before; a failure names the file, the line and the field. Facet and flock indices are
/// checked against the stone by [`check_outcomes`].
pub fn read_partial(path: &Path) -> Result<(RunHeader, BTreeMap<u64, DropOutcome>)> {
    let io = |e: std::io::Error| Error::Io { path: path.into(), error: e };
    let parse = |what: String| Error::Parse { path: path.into(), what };
    let bytes = std::fs::read(path).map_err(io)?;
    let mut lines: Vec<&[u8]> = bytes.split(|&b| b == b'\n').collect();
    if lines.last().is_some_and(|l| l.is_empty()) {
        lines.pop();
    }
    let text = |k: usize, l: &[u8]| -> Result<String> {
        String::from_utf8(l.to_vec()).map_err(|e| parse(format!("line {}: not UTF-8 text ({e})", k + 1)))
    };
    let first = lines.first().ok_or_else(|| parse("empty file: not a drop result".into()))?;
    let header: RunHeader =
        serde_json::from_str(&text(0, first)?).map_err(|e| parse(format!("line 1 is not a drop-run header: {e}")))?;
    if header.format != FORMAT {
        return Err(parse(format!("unknown format {:?} (expected {FORMAT:?})", header.format)));
    }
    if header.shard.count == 0 || header.shard.index >= header.shard.count {
        return Err(parse(format!(
            "line 1: field shard: {}/{} is not a shard",
            header.shard.index, header.shard.count
        )));
    }
    let mut outcomes = BTreeMap::new();
    let mut seen: BTreeMap<u64, usize> = BTreeMap::new();
    let last = lines.len();
    for (k, raw) in lines.iter().enumerate().skip(1) {
        let line = k + 1;
        let o = match String::from_utf8(raw.to_vec()).ok().and_then(|t| serde_json::from_str::<DropOutcome>(&t).ok()) {
            Some(o) => o,
            None if k + 1 == last => break, // interrupted while writing the last line
            None => {
                let t = text(k, raw)?;
                let e = serde_json::from_str::<DropOutcome>(&t).err().map_or(String::new(), |e| e.to_string());
                return Err(parse(format!("line {line}: not a drop outcome: {e}")));
            }
        };
        if o.index >= header.drops {
            return Err(parse(format!(
                "line {line}: field index: drop {} is beyond the run's {} drops",
                o.index, header.drops
            )));
        }
        if !header.shard.holds(o.index) {
            return Err(parse(format!(
                "line {line}: field index: drop {} does not belong to shard {}/{}",
                o.index, header.shard.index, header.shard.count
            )));
        }
        if let Some(prev) = seen.insert(o.index, line) {
            return Err(parse(format!("line {line}: field index: drop {} is already on line {prev}", o.index)));
        }
        if !(o.time.is_finite() && o.time >= 0.0) {
            return Err(parse(format!("line {line}: field time: {} is not a simulated time", o.time)));
        }
        outcomes.insert(o.index, o);
    }
    Ok((header, outcomes))
}

/// Check outcomes read from `path` against the stone they are summarised on: every facet a stable
/// facet of its hull, every flock one of its flocks. Errors name the file, the drop and the field.
pub fn check_outcomes(path: &Path, outcomes: &BTreeMap<u64, DropOutcome>, model: &StaticModel) -> Result<()> {
    let bad = |what: String| Err(Error::Parse { path: path.into(), what });
    for o in outcomes.values() {
        if let Some(f) = o.facet {
            match model.facet_equilibrium.get(f as usize) {
                None => {
                    return bad(format!(
                        "drop {}: field facet: {f} is beyond the hull's {} facets",
                        o.index,
                        model.facet_equilibrium.len()
                    ))
                }
                Some(None) => return bad(format!("drop {}: field facet: {f} is not a stable facet", o.index)),
                Some(Some(_)) => {}
            }
        }
        if let Some(k) = o.flock {
            if k as usize >= model.flock_kinds.len() {
                return bad(format!(
                    "drop {}: field flock: {k} is beyond the stone's {} flocks",
                    o.index,
                    model.flock_kinds.len()
                ));
            }
        }
    }
    Ok(())
}

/// Combine partial results of one run. Headers must agree; an index present twice must have
/// the same outcome.
pub fn merge(parts: &[(RunHeader, BTreeMap<u64, DropOutcome>)]) -> Result<(RunHeader, BTreeMap<u64, DropOutcome>)> {
    let (first, _) = parts.first().ok_or_else(|| Error::Usage("nothing to merge".into()))?;
    let mut all = BTreeMap::new();
    for (h, outcomes) in parts {
        let differ = first.differences(h);
        if !differ.is_empty() {
            return Err(Error::Usage(format!(
                "partial results of different runs cannot be merged: they differ in {}",
                differ.join(", ")
            )));
        }
        for (i, o) in outcomes {
            if let Some(prev) = all.insert(*i, *o) {
                if prev != *o {
                    return Err(Error::Usage(format!("drop {i} has two different outcomes in the partial results")));
                }
            }
        }
    }
    let mut header = first.clone();
    header.shard = Shard::ALL;
    Ok((header, all))
}

/// Per-facet row of a drop report.
#[derive(Clone, Debug, Serialize)]
pub struct FacetRow {
    /// Hull facet index.
    pub facet: u32,
    /// Outward unit normal of the facet (mesh frame).
    pub normal: Vec3,
    /// Index of the stable micro-equilibrium on it (None: the facet is not stable).
    pub equilibrium: Option<usize>,
    /// Flock of that equilibrium at ν (None: the facet is not stable).
    pub flock: Option<usize>,
    /// Settled drops that ended on the facet.
    pub count: u64,
    /// Fraction of the settled drops with a determined facet that ended on it.
    pub fraction: f64,
    /// 95 % Wilson interval of `fraction`.
    pub ci95: (f64, f64),
    /// Quasi-static resting probability of the facet (basin area / 4π).
    pub static_probability: f64,
}

/// Per-flock row of a drop report.
#[derive(Clone, Debug, Serialize)]
pub struct FlockRow {
    /// Flock id.
    pub id: usize,
    #[serde(rename = "type")]
    /// Type of the flock (stable, unstable or saddle).
    pub kind: Kind,
    /// Settled drops that ended in the flock.
    pub count: u64,
    /// Fraction of the settled drops with a known flock that ended in it.
    pub fraction: f64,
    /// 95 % Wilson interval of `fraction`.
    pub ci95: (f64, f64),
    /// Quasi-static resting probability of the flock (sum over its facets).
    pub static_probability: f64,
}

/// Goodness of fit of the drops against the static probabilities.
#[derive(Clone, Debug, Serialize)]
pub struct Fit {
    /// Pearson χ² statistic of the counts against the static probabilities.
    pub chi_square: f64,
    /// Degrees of freedom of the χ² test.
    pub dof: usize,
    /// p-value of the χ² test (NaN, `null` in JSON, when it has no degree of freedom: no drop
    /// came to rest, or all fell in one category).
    pub p_value: f64,
    /// Kullback–Leibler divergence D(empirical ‖ static) in nats.
    pub kl_divergence: f64,
}

/// The numbers of a drop run, read by the CLI, the plots and the experiments.
#[derive(Clone, Debug, Serialize)]
pub struct DropReport {
    /// The mesh file as given.
    pub mesh: String,
    /// Seed of the random streams of the drops.
    pub seed: u64,
    /// Drops asked for in the run.
    pub drops_requested: u64,
    /// Drops present in these results (all of them unless partial).
    pub drops: u64,
    /// Drops that came to rest (or were decided by the certificate).
    pub settled: u64,
    /// Drops still moving at the time cap: left out of every count, fraction and fit (a drop that
    /// has not come to rest has no resting position; assigning it the quasi-static descent from
    /// where it was would count a guess as an outcome).
    pub unsettled: u64,
    /// Settled drops that stopped above their stable facet by more than the contact tolerance
    /// ([`crate::dynamics::stone::REST_TOLERANCE`]): held on a slope by friction or rolling
    /// resistance. Their facet is the one the quasi-static descent reaches.
    pub off_equilibrium: u64,
    /// Drops ended by the energy certificate.
    pub certified: u64,
    /// The deepest any hull corner went below the ground after any step or sub-step of any drop
    /// of the run (R_max; [`crate::dynamics::engine::world::penetration`]).
    pub deepest_penetration: f64,
    /// Drops whose deepest penetration exceeded [`crate::dynamics::engine::impact::DEPTH_BOUND`].
    pub drops_beyond_depth_bound: u64,
    /// Mean simulated time per drop (s, scaled frame), whatever ended it.
    pub mean_time: f64,
    /// Mean simulated time to rest of the drops that came to rest without the certificate.
    pub mean_time_to_rest: Option<f64>,
    /// Mean simulated time to the certificate's decision of the certified drops.
    pub mean_time_to_decision: Option<f64>,
    /// Drops whose final facet is determined (settled and not ended by a flock-level
    /// certificate): the per-facet fractions are over these.
    pub facet_drops: u64,
    /// Simulation parameters of the drops.
    pub params: DropParams,
    /// The preset the parameters started from, if any.
    pub preset: Option<String>,
    /// Whether and how the energy certificate may end a drop.
    pub certificate: CertificateMode,
    /// Resolution ν of the flocks.
    pub nu: f64,
    /// Facets that were reached or have a positive static probability (empty in flock-certified
    /// mode, where the certificate leaves facets undetermined).
    pub facets: Vec<FacetRow>,
    /// One row per flock.
    pub flocks: Vec<FlockRow>,
    /// χ² / KL of settled drops on stable facets against the static facet probabilities
    /// (None in flock-certificate mode, where facets are not decided).
    pub fit_facets: Option<Fit>,
    /// χ² / KL of the drops by flock against the static flock probabilities.
    pub fit_flocks: Fit,
}

/// Summarise the outcomes of a run (or a merged set of partial runs).
pub fn summarize(model: &StaticModel, header: &RunHeader, outcomes: &BTreeMap<u64, DropOutcome>) -> DropReport {
    let nf = model.facet_normals.len();
    let mut facet_counts = vec![0u64; nf];
    let mut flock_counts = vec![0u64; model.flock_kinds.len()];
    let (mut settled, mut unsettled, mut off, mut certified, mut time) = (0, 0, 0, 0, 0.0);
    let (mut rest_time, mut rested, mut decision_time) = (0.0, 0u64, 0.0);
    let (mut deepest, mut beyond) = (0.0f64, 0u64);
    for o in outcomes.values() {
        time += o.time;
        deepest = deepest.max(o.deepest_penetration);
        beyond += u64::from(o.deepest_penetration > crate::dynamics::engine::impact::DEPTH_BOUND);
        certified += u64::from(o.certified);
        if o.certified {
            decision_time += o.time;
        } else if o.settled {
            rest_time += o.time;
            rested += 1;
        }
        if !o.settled {
            unsettled += 1;
            continue;
        }
        settled += 1;
        off += u64::from(o.off_equilibrium());
        if let Some(f) = o.facet {
            facet_counts[f as usize] += 1;
        }
        let flock = o.flock.map(|k| k as usize).or_else(|| o.facet.and_then(|f| model.facet_flock[f as usize]));
        if let Some(k) = flock {
            flock_counts[k] += 1;
        }
    }
    let flock_probability: Vec<f64> = (0..model.flock_kinds.len())
        .map(|k| (0..nf).filter(|&f| model.facet_flock[f] == Some(k)).map(|f| model.facet_probability[f]).sum())
        .collect();
    let n_facet: u64 = facet_counts.iter().sum();
    let facets_determined = header.certificate != CertificateMode::Flock;
    let facets = (0..nf)
        .filter(|&f| facets_determined && (facet_counts[f] > 0 || model.facet_probability[f] > 0.0))
        .map(|f| FacetRow {
            facet: f as u32,
            normal: model.facet_normals[f],
            equilibrium: model.facet_equilibrium[f],
            flock: model.facet_flock[f],
            count: facet_counts[f],
            fraction: if n_facet > 0 { facet_counts[f] as f64 / n_facet as f64 } else { 0.0 },
            ci95: wilson(facet_counts[f], n_facet, 1.96),
            static_probability: model.facet_probability[f],
        })
        .collect();
    let n_flock: u64 = flock_counts.iter().sum();
    let flocks = (0..model.flock_kinds.len())
        .filter(|&k| flock_counts[k] > 0 || flock_probability[k] > 0.0)
        .map(|k| FlockRow {
            id: k,
            kind: model.flock_kinds[k],
            count: flock_counts[k],
            fraction: if n_flock > 0 { flock_counts[k] as f64 / n_flock as f64 } else { 0.0 },
            ci95: wilson(flock_counts[k], n_flock, 1.96),
            static_probability: flock_probability[k],
        })
        .collect();
    // A test with no degrees of freedom (no drop, or one category) has no p-value (null in
    // JSON), and a divergence that rounds below zero is zero.
    let fit = |counts: &[u64], p: &[f64]| {
        let (chi_square, dof, p_value) = chi_square(counts, p);
        let kl = kl_divergence(counts, p);
        Fit {
            chi_square,
            dof,
            p_value: if dof > 0 { p_value } else { f64::NAN },
            kl_divergence: if kl > 0.0 { kl } else { 0.0 },
        }
    };
    let fit_facets = facets_determined.then(|| fit(&facet_counts, &model.facet_probability));
    let mean = |t: f64, n: u64| (n > 0).then(|| t / n as f64);
    DropReport {
        mesh: header.mesh.clone(),
        seed: header.seed,
        drops_requested: header.drops,
        drops: outcomes.len() as u64,
        settled,
        unsettled,
        off_equilibrium: off,
        certified,
        deepest_penetration: deepest,
        drops_beyond_depth_bound: beyond,
        mean_time: if outcomes.is_empty() { 0.0 } else { time / outcomes.len() as f64 },
        mean_time_to_rest: mean(rest_time, rested),
        mean_time_to_decision: mean(decision_time, certified),
        facet_drops: if facets_determined { n_facet } else { 0 },
        params: header.params.clone(),
        preset: header.preset.clone(),
        certificate: header.certificate,
        nu: model.nu,
        facets,
        flocks,
        fit_facets,
        fit_flocks: fit(&flock_counts, &flock_probability),
    }
}

/// Run every drop of `header` in memory (no checkpoint, no progress) and summarise them; for
/// experiments and tests. Returns the report and the outcomes by index.
pub fn run_and_summarize(stone: &Stone, header: &RunHeader) -> (DropReport, BTreeMap<u64, DropOutcome>) {
    let sink = Mutex::new(|_: &DropOutcome| {});
    let cert = certificate(stone, header.certificate);
    let outcomes: BTreeMap<u64, DropOutcome> =
        run_drops(stone, header, Shard::ALL, &BTreeMap::new(), cert.as_ref(), &sink)
            .into_iter()
            .map(|o| (o.index, o))
            .collect();
    (summarize(&stone.model(), header, &outcomes), outcomes)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shards_partition_the_indices() {
        let mut all: Vec<u64> =
            (0..3).flat_map(|i| Shard { index: i, count: 3 }.indices(10).collect::<Vec<_>>()).collect();
        all.sort();
        assert_eq!(all, (0..10).collect::<Vec<_>>());
        assert!(Shard::parse("3/3").is_err() && Shard::parse("1/0").is_err() && Shard::parse("x").is_err());
        assert_eq!(Shard::parse("1/4").unwrap(), Shard { index: 1, count: 4 });
    }
}
