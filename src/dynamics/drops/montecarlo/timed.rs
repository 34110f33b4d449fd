//! Drop runs timed by the CPU time of the thread that runs them ([`run_timed`]): drops per second
//! per core on a machine shared with other jobs, where wall time counts the other jobs' time
//! slices and the CPU time of the running thread does not.

use crate::dynamics::certificate::certificate;
use crate::dynamics::drops::launch::DropOutcome;
use crate::dynamics::drops::montecarlo::{run_drops_batched, summarize, DropReport, RunHeader};
use crate::dynamics::stone::Stone;
use crate::{Error, Result};
use std::collections::BTreeMap;
use std::sync::Mutex;

/// CPU time of the calling thread (s), from the `cpu-time` crate's per-thread clock
/// (`CLOCK_THREAD_CPUTIME_ID` on Linux and the BSDs and macOS, `GetThreadTimes` on Windows): the
/// time the thread spent on a CPU, not the time it waited for one. [`Error::Clock`] on a platform
/// without such a clock.
pub fn thread_cpu_seconds() -> Result<f64> {
    Ok(cpu_time::ThreadTime::try_now().map_err(Error::Clock)?.as_duration().as_secs_f64())
}

/// A drop run timed by [`run_timed`]: its summary, its outcomes by drop index, and the CPU
/// seconds of its drops.
pub struct TimedRun {
    /// The run's summary ([`summarize`]).
    pub report: DropReport,
    /// The outcomes by drop index.
    pub outcomes: BTreeMap<u64, DropOutcome>,
    /// CPU seconds of the drops alone, on the one thread that ran them.
    pub seconds: f64,
}

impl TimedRun {
    /// Drops per CPU second: the report's drops ÷ [`TimedRun::seconds`].
    pub fn rate(&self) -> f64 {
        self.report.drops as f64 / self.seconds
    }

    /// The faster of two timings of the same drops: `other` if it took fewer CPU seconds, else
    /// this one.
    pub fn faster(self, other: TimedRun) -> TimedRun {
        if other.seconds < self.seconds {
            other
        } else {
            self
        }
    }

    /// CPU µs per simulated step: 10⁶ × seconds ÷ (drops × mean simulated time ÷ dt), the steps
    /// of every drop, each counted once whatever the number of stones in its world.
    pub fn micros_per_step(&self) -> f64 {
        let steps = self.report.drops as f64 * self.report.mean_time / self.report.params.sim.numerics.dt;
        1e6 * self.seconds / steps
    }
}

/// Every drop of `header` with `batch` stones per world ([`run_drops_batched`]) run on `pool`,
/// timed by the CPU time of the pool's worker thread ([`thread_cpu_seconds`]): the drops alone,
/// not the certificate's construction nor the summary. With a pool of one thread (as meant) the
/// seconds are those of the whole run on one core; with more, those of one of its threads.
pub fn run_timed(pool: &rayon::ThreadPool, stone: &Stone, header: &RunHeader, batch: usize) -> Result<TimedRun> {
    pool.install(|| {
        let sink = Mutex::new(|_: &DropOutcome| {});
        let cert = certificate(stone, header.certificate);
        let start = thread_cpu_seconds()?;
        let out = run_drops_batched(stone, header, &BTreeMap::new(), cert.as_ref(), batch, &sink);
        let seconds = thread_cpu_seconds()? - start;
        let outcomes: BTreeMap<u64, DropOutcome> = out.into_iter().map(|o| (o.index, o)).collect();
        Ok(TimedRun { report: summarize(&stone.model(), header, &outcomes), outcomes, seconds })
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::{Analysis, Options};
    use crate::dynamics::certificate::CertificateMode;
    use crate::dynamics::drops::montecarlo::run_and_summarize;
    use crate::dynamics::drops::params::Preset;
    use crate::dynamics::surface::Surface;
    use std::time::{Duration, Instant};

    #[test]
    fn the_thread_clock_counts_work_and_not_sleep() {
        // Busy for 30 ms of CPU: never more CPU time than wall time has passed.
        let (cpu, wall) = (thread_cpu_seconds().unwrap(), Instant::now());
        let mut x = 0u64;
        while thread_cpu_seconds().unwrap() - cpu < 0.03 {
            x = x.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1);
        }
        let busy = thread_cpu_seconds().unwrap() - cpu;
        assert!(busy >= 0.03 && busy <= wall.elapsed().as_secs_f64() + 1e-3, "{busy} s of CPU ({x})");
        // Asleep for 200 ms: the thread is off the CPU.
        let cpu = thread_cpu_seconds().unwrap();
        std::thread::sleep(Duration::from_millis(200));
        assert!(thread_cpu_seconds().unwrap() - cpu < 0.05);
    }

    #[test]
    fn a_timed_run_has_the_outcomes_of_the_untimed_one() {
        let (mesh, repairs) = crate::generate::cuboid(1.0, 0.8, 0.5).into_solid_boundary().unwrap();
        let a = Analysis::of_solid(mesh, repairs, &Options::default()).unwrap();
        let stone = Stone::new(&a, a.macro_nu(&Options::default()).0).unwrap();
        let params = Preset::Drop.params(Surface::SteelOnWood);
        let header = RunHeader::of_params("box", 3, 40, params.clone(), CertificateMode::None);
        let pool = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap();
        let run = run_timed(&pool, &stone, &header, 4).unwrap();
        // Batched drops end as the same drops alone (`tests/batch.rs`).
        let (report, outcomes) = run_and_summarize(&stone, &header);
        assert_eq!(run.outcomes, outcomes);
        assert_eq!((run.report.drops, run.report.settled), (40, report.settled));
        assert!(run.seconds > 0.0 && (run.rate() - 40.0 / run.seconds).abs() < 1e-9 * run.rate());
        // The steps of the drops, counted from their own simulated times.
        let steps = outcomes.values().map(|o| o.time).sum::<f64>() / params.sim.numerics.dt;
        assert!((run.micros_per_step() - 1e6 * run.seconds / steps).abs() < 1e-6 * run.micros_per_step());
        // The faster of two timings; a tie keeps the first.
        let timing = |seconds| TimedRun { report: report.clone(), outcomes: outcomes.clone(), seconds };
        assert_eq!(timing(2.0).faster(timing(1.5)).seconds, 1.5);
        assert_eq!(timing(1.5).faster(timing(2.0)).seconds, 1.5);
        let (first, second) = (timing(1.0), TimedRun { outcomes: BTreeMap::new(), ..timing(1.0) });
        assert_eq!(first.faster(second).outcomes.len(), 40);
    }
}
