//! The harness every experiment runs on: its command line (clap), its results folder, CSV
//! files, and its `README.md` rendered from a template in `experiments/readme/`.
//!
//! An experiment is `fn main() -> Result<()>`: it parses its arguments (a clap struct that
//! flattens [`Common`]), opens its [`Results`] folder, computes through the library, writes
//! CSV with [`Results::csv`], plots with the library's [`rocking_stones::plot::Chart`], and
//! renders its README with [`Results::readme`]: the prose lives in the template, the numbers
//! come from the run. Experiments import it as `use experiments::harness;`.

pub use anyhow::{Context, Result};
pub use clap::Parser;
use serde::Serialize;
use std::path::{Path, PathBuf};

/// The repository's root folder, where `data/` and `results/` are.
pub fn repo() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR")).parent().expect("the experiments package is a folder of the repository")
}

/// The arguments every experiment takes.
#[derive(clap::Args, Debug, Clone)]
pub struct Common {
    /// Folder to write the results to [default: results/<the experiment's folder> in the
    /// repository]
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// Seed of every random draw [default: the experiment's own, so that a rerun reproduces the
    /// committed results]
    #[arg(long)]
    pub seed: Option<u64>,
}

impl Common {
    /// The seed: `--seed` if given, the experiment's `default` otherwise.
    pub fn seed_or(&self, default: u64) -> u64 {
        self.seed.unwrap_or(default)
    }
}

/// The command line of an experiment that has no arguments of its own: [`Common`], its `--help`
/// saying `about`.
pub fn common_args(about: &str) -> Common {
    use clap::{Args, FromArgMatches};
    let command = Common::augment_args(clap::Command::new(env!("CARGO_PKG_NAME"))).about(about.to_owned());
    Common::from_arg_matches(&command.get_matches()).unwrap_or_else(|e| e.exit())
}

/// The command line of an experiment whose one argument of its own is a count: `[N]`, its help
/// `count` and its default `default`, then [`Common`]; `--help` says `about`.
pub fn count_args(about: &str, count: &str, default: u64) -> (u64, Common) {
    use clap::{Arg, Args, FromArgMatches};
    let n = Arg::new("n").value_name("N").help(count.to_owned()).default_value(default.to_string());
    let command = Common::augment_args(clap::Command::new(env!("CARGO_PKG_NAME")));
    let matches = command.arg(n.value_parser(clap::value_parser!(u64))).about(about.to_owned()).get_matches();
    let common = Common::from_arg_matches(&matches).unwrap_or_else(|e| e.exit());
    (matches.get_one::<u64>("n").copied().unwrap_or(default), common)
}

/// The results folder of one experiment.
pub struct Results {
    dir: PathBuf,
}

impl Results {
    /// Open (create) the results folder: `--out` if given, `results/<folder>` of the repository
    /// otherwise.
    pub fn open(folder: &str, common: &Common) -> Result<Self> {
        let dir = match &common.out {
            Some(d) => d.clone(),
            None => repo().join("results").join(folder),
        };
        std::fs::create_dir_all(&dir).with_context(|| format!("cannot create the results folder {}", dir.display()))?;
        Ok(Results { dir })
    }

    /// The path of `file` in the folder.
    pub fn path(&self, file: &str) -> PathBuf {
        self.dir.join(file)
    }

    /// Write `text` to `file`.
    pub fn write(&self, file: &str, text: impl AsRef<[u8]>) -> Result<()> {
        let path = self.path(file);
        std::fs::write(&path, text).with_context(|| format!("cannot write {}", path.display()))
    }

    /// Write a CSV `file`: the `header`, then one record per row (each already formatted).
    pub fn csv<R, S>(&self, file: &str, header: &[&str], rows: impl IntoIterator<Item = R>) -> Result<()>
    where
        R: IntoIterator<Item = S>,
        S: AsRef<[u8]>,
    {
        let path = self.path(file);
        let mut w = csv::Writer::from_path(&path).with_context(|| format!("cannot write {}", path.display()))?;
        w.write_record(header)?;
        for row in rows {
            w.write_record(row)?;
        }
        w.flush().with_context(|| format!("cannot write {}", path.display()))
    }

    /// Render `template` (an `experiments/readme/*.md`, included with `include_str!`) with the
    /// run's values `context` and write it as the folder's `README.md`. A value the template
    /// names but the context lacks is an error, not an empty string.
    pub fn readme(&self, template: &str, context: impl Serialize) -> Result<()> {
        self.page("README.md", template, context)
    }

    /// [`Results::readme`] written as `file`: one page of a folder that several experiments share.
    pub fn page(&self, file: &str, template: &str, context: impl Serialize) -> Result<()> {
        let text = render(template, context)?;
        self.write(file, text)
    }
}

/// Render a README template: minijinja with blocks trimmed (a `{% … %}` line leaves no blank
/// line), the trailing newline kept, and undefined values an error.
pub fn render(template: &str, context: impl Serialize) -> Result<String> {
    let mut env = minijinja::Environment::new();
    env.set_syntax(
        minijinja::syntax::SyntaxConfig::builder()
            .trim_blocks(true)
            .lstrip_blocks(true)
            .keep_trailing_newline(true)
            .build()?,
    );
    env.set_undefined_behavior(minijinja::UndefinedBehavior::Strict);
    env.add_template("readme", template).context("the README template does not parse")?;
    let t = env.get_template("readme")?;
    t.render(minijinja::value::Serde(context)).context("the README template does not render")
}

/// The folder of shake-table tests `dir` (not part of the repository: GPL-3.0) with the rows of
/// its `tests.csv`; None, said on stderr, when it is not given (`holds`: what it must hold).
pub fn shake_table_tests<T: serde::de::DeserializeOwned>(
    name: &str,
    dir: &Option<PathBuf>,
    holds: &str,
) -> Result<Option<(PathBuf, Vec<T>)>> {
    let Some(dir) = dir else {
        eprintln!(
            "{name}: skipped — give the folder of the shake-table tests ({holds}) as the argument; it is not part of \
             the repository"
        );
        return Ok(None);
    };
    let table = dir.join("tests.csv");
    let mut reader = csv::Reader::from_path(&table).with_context(|| format!("cannot read {}", table.display()))?;
    let tests = reader.deserialize().collect::<std::result::Result<_, _>>().context("tests.csv")?;
    Ok(Some((dir.clone(), tests)))
}

/// A number with `digits` decimals, as the READMEs write it.
pub fn fixed(x: f64, digits: usize) -> String {
    format!("{x:.digits$}")
}

/// A table cell: `{:.prec$e}` if `e`, else `prec` decimals; "∞", "−∞" or "–" where the number
/// is infinite or undefined.
pub fn cell(x: f64, prec: usize, e: bool) -> String {
    match x {
        x if x.is_nan() => "–".into(),
        x if x.is_infinite() => if x > 0.0 { "∞" } else { "−∞" }.into(),
        x if e => format!("{x:.prec$e}"),
        x => fixed(x, prec),
    }
}

/// A CSV header written as one line, split at its commas (no column name holds one).
pub fn columns(header: &str) -> Vec<&str> {
    header.split(',').collect()
}

/// The value of `f` and the wall-clock seconds it took.
pub fn timed<T>(f: impl FnOnce() -> T) -> (T, f64) {
    let t0 = std::time::Instant::now();
    (f(), t0.elapsed().as_secs_f64())
}
