//! Errors a person can act on: every variant names the file (when there is one) and what is wrong.

use std::path::PathBuf;

/// Result alias of the library.
pub type Result<T, E = Error> = std::result::Result<T, E>;

/// What can go wrong between a scan on disk and its equilibria.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// The file could not be read or written.
    #[error("{path}: {error}")]
    Io {
        /// The file concerned (`<memory>` for meshes built in memory).
        path: PathBuf,
        /// The underlying I/O error.
        error: std::io::Error,
    },
    /// The file is not a mesh we can parse (format, truncation, bad numbers...).
    #[error("{path}: {what}")]
    Parse {
        /// The file concerned (`<memory>` for meshes built in memory).
        path: PathBuf,
        /// What could not be parsed, and where in the file.
        what: String,
    },
    /// The mesh parsed but is not a closed, manifold, consistently oriented solid.
    #[error("{path}: {what}")]
    InvalidMesh {
        /// The file concerned (`<memory>` for meshes built in memory).
        path: PathBuf,
        /// Which property of a solid boundary fails.
        what: String,
    },
    /// The geometry is degenerate (flat, empty, zero volume, all points coplanar...).
    #[error("{path}: degenerate geometry: {what}")]
    Degenerate {
        /// The file concerned (`<memory>` for meshes built in memory).
        path: PathBuf,
        /// In what way the geometry is degenerate.
        what: String,
    },
    /// The surface crosses itself: two triangles (numbered as in the file, from 0) that share no
    /// edge intersect beyond their common vertices. Such a surface bounds no solid, and its G can
    /// even fall outside the hull.
    #[error("{path}: the surface intersects itself: triangles {first} and {second} cross{}, {depth:.3e} deep ({relative_depth:.1e} of the size; {pairs} crossing pair(s) in all); a stone must be a closed surface that does not pass through itself", near_text(.near))]
    SelfIntersecting {
        /// The file concerned (`<memory>` for meshes built in memory).
        path: PathBuf,
        /// Index of the first crossing triangle, as numbered in the file.
        first: usize,
        /// Index of the second crossing triangle, as numbered in the file.
        second: usize,
        /// Number of crossing triangle pairs in the whole mesh.
        pairs: usize,
        /// How deep the deepest pair crosses (input units).
        depth: f64,
        /// That depth divided by the diameter of the mesh.
        relative_depth: f64,
        /// Approximate point where the two triangles meet (input units), if known.
        near: Option<[f64; 3]>,
    },
    /// The centre of mass lies outside (or on) the convex hull, so the stone cannot rest anywhere:
    /// the mesh is not the boundary of a solid (e.g. it intersects itself) or a given G is wrong.
    #[error("{path}: the centre of mass G = ({}, {}, {}) is not inside the convex hull: {what}", .g[0], .g[1], .g[2])]
    CentreOutsideHull {
        /// The file concerned (`<memory>` for meshes built in memory).
        path: PathBuf,
        /// The centre of mass G (input units).
        g: [f64; 3],
        /// How G lies relative to the hull.
        what: String,
    },
    /// A theorem that must hold failed (e.g. Poincaré–Hopf); this is a bug or a degenerate input.
    #[error("{path}: internal check failed: {what}")]
    Check {
        /// The file concerned (`<memory>` for meshes built in memory).
        path: PathBuf,
        /// Which check failed, with its numbers.
        what: String,
    },
    /// A plot could not be drawn into the file.
    #[error("{path}: cannot draw the plot: {what}")]
    Plot {
        /// The plot file being written.
        path: PathBuf,
        /// What the plotting library reported.
        what: String,
    },
    /// A parameter outside the range it must lie in, named as the library names it: the field of
    /// a parameter struct (`dt`, `max_time`, `friction`, `length_unit`…). The command line turns
    /// the name into its flag (`--max-time`), the Python binding into its keyword (`max_time=`).
    #[error("{name} must be {expected}, got {value}")]
    Parameter {
        /// The parameter's name in the library (a struct field or function argument).
        name: String,
        /// The value given, as written.
        value: String,
        /// The range or form it must have.
        expected: String,
    },
    /// A name that is not one of those known: a preset, a surface, a shape, a unit, a family.
    #[error("unknown {what} {given:?}: expected one of {}", .allowed.join(", "))]
    Unknown {
        /// What kind of name was expected (`contact model`, `acceleration unit`…).
        what: &'static str,
        /// The name given.
        given: String,
        /// The names known.
        allowed: Vec<String>,
    },
    /// A ground motion (a record or a synthetic motion) that cannot drive a run: too short, not
    /// finite, irregularly sampled, without horizontal acceleration, or given in a form not read.
    #[error("{name}: {what}")]
    Motion {
        /// The motion's name (its file, or the kind of synthetic motion).
        name: String,
        /// What is wrong with it, and what to do.
        what: String,
    },
    /// A pose in which a stone does not stand: not a stable equilibrium, or put down it rolls
    /// away or does not come to rest.
    #[error("pose {pose}: {what}")]
    Pose {
        /// The pose as given (`facet:3`, `as-scanned`, `quat:…`).
        pose: String,
        /// Why the stone does not stand in it, and what to choose instead.
        what: String,
    },
    /// A dynamic run on a mesh whose real size is neither given nor known: its result depends on
    /// the size, and no one guess is right for dice and field rocks ([`crate::dynamics::size`]).
    #[error("{mesh}: {}", size_unknown(*one_stone, &|n: &str| n.to_string()))]
    SizeUnknown {
        /// The mesh concerned, as reported.
        mesh: String,
        /// One stone, whose size may also be given as its R_max (`size`); false for a folder of
        /// scans of many sizes, which only their length unit can size.
        one_stone: bool,
    },
    /// Results of long runs that do not belong together: a checkpoint written by a different
    /// run, or partial results that differ in their parameters or outcomes.
    #[error("{0}")]
    Checkpoint(String),
    /// A model that cannot be fitted to what it was given (a fragility surface to runs that all
    /// ended alike, ν to samples without statistics…).
    #[error("cannot fit {0}")]
    Fit(String),
    /// A field study whose folder or table does not match its scans.
    #[error("{path}: {what}")]
    Study {
        /// The folder or table concerned.
        path: PathBuf,
        /// What does not match.
        what: String,
    },
    /// The CPU clock of the calling thread cannot be read: a platform without a per-thread CPU
    /// clock, on which drops cannot be timed per core.
    #[error("cannot read the thread's CPU clock: {0}")]
    Clock(std::io::Error),
    /// The caller stopped a long run ([`crate::monitor::Monitor::stopped`]).
    #[error("the run was stopped before it finished")]
    Cancelled,
    /// An open surface that cannot be read as a field scan standing on its hidden base
    /// (`crate::mesh::open_scan`): which [`ScanProblem`], and what to give instead.
    #[error("{path}: {what}")]
    OpenScan {
        /// The file concerned (`<memory>` for meshes built in memory).
        path: PathBuf,
        /// Which reading failed.
        problem: ScanProblem,
        /// What was found, and what to give instead.
        what: String,
    },
}

/// Why a surface is not read as an open scan ([`Error::OpenScan`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum ScanProblem {
    /// The surface has no boundary: it is a closed stone, not an open scan (read it as one).
    Closed,
    /// The largest opening is not at the base: the scan is open at its top or side.
    OpenTop,
    /// Several openings of comparable size: which one is the rim of the hidden base is not clear.
    SeveralRims,
    /// An opening that does not project onto its best-fit plane as a simple polygon.
    NotSimple,
    /// A closing surface (a base or the patch of a gap) crosses the scan.
    Crossing,
}

/// Any error of a writer's inner steps (CSV, JSON, I/O, plotters), before it is given its file.
pub type BoxError = Box<dyn std::error::Error + Send + Sync>;

impl Error {
    /// Attach a file name to an error that was produced without one (path `<memory>`).
    pub fn with_path(self, p: impl Into<PathBuf>) -> Self {
        let p = p.into();
        let fix = |old: PathBuf| if old.as_os_str() == MEMORY { p.clone() } else { old };
        match self {
            Error::Io { path, error } => Error::Io { path: fix(path), error },
            Error::Parse { path, what } => Error::Parse { path: fix(path), what },
            Error::InvalidMesh { path, what } => Error::InvalidMesh { path: fix(path), what },
            Error::Degenerate { path, what } => Error::Degenerate { path: fix(path), what },
            Error::Check { path, what } => Error::Check { path: fix(path), what },
            Error::Plot { path, what } => Error::Plot { path: fix(path), what },
            Error::SelfIntersecting { path, first, second, pairs, depth, relative_depth, near } => {
                Error::SelfIntersecting { path: fix(path), first, second, pairs, depth, relative_depth, near }
            }
            Error::CentreOutsideHull { path, g, what } => Error::CentreOutsideHull { path: fix(path), g, what },
            Error::Study { path, what } => Error::Study { path: fix(path), what },
            Error::OpenScan { path, problem, what } => Error::OpenScan { path: fix(path), problem, what },
            e @ (Error::Unknown { .. }
            | Error::Motion { .. }
            | Error::Pose { .. }
            | Error::Checkpoint(_)
            | Error::Fit(_)
            | Error::Parameter { .. }
            | Error::SizeUnknown { .. }
            | Error::Clock(_)
            | Error::Cancelled) => e,
        }
    }

    /// A failure while writing file `path` (CSV, JSON or I/O), as [`Error::Io`] naming the file;
    /// `path` = [`MEMORY`] for a writer into a stream, to be named with [`Error::with_path`].
    pub fn write(path: impl Into<PathBuf>, e: impl Into<BoxError>) -> Self {
        let error = match e.into().downcast::<std::io::Error>() {
            Ok(io) => *io,
            Err(other) => std::io::Error::other(other),
        };
        Error::Io { path: path.into(), error }
    }

    /// Shorthand for an in-memory degenerate-geometry error.
    pub fn degenerate(what: impl Into<String>) -> Self {
        Error::Degenerate { path: MEMORY.into(), what: what.into() }
    }

    /// Shorthand for an in-memory invalid-mesh error.
    pub fn invalid(what: impl Into<String>) -> Self {
        Error::InvalidMesh { path: MEMORY.into(), what: what.into() }
    }

    /// A short stable name of the error's kind (`io`, `parse`, `invalid-mesh`, `degenerate`,
    /// `self-intersecting`, `centre-outside-hull`, `internal-check`, `plot`, `parameter`,
    /// `size-unknown`, `unknown-name`, `motion`, `pose`, `checkpoint`, `fit`, `study`, `clock`,
    /// `cancelled`, `open-scan`), for tallies.
    pub fn kind(&self) -> &'static str {
        match self {
            Error::Io { .. } => "io",
            Error::Parse { .. } => "parse",
            Error::InvalidMesh { .. } => "invalid-mesh",
            Error::Degenerate { .. } => "degenerate",
            Error::SelfIntersecting { .. } => "self-intersecting",
            Error::CentreOutsideHull { .. } => "centre-outside-hull",
            Error::Check { .. } => "internal-check",
            Error::Plot { .. } => "plot",
            Error::Parameter { .. } => "parameter",
            Error::SizeUnknown { .. } => "size-unknown",
            Error::Unknown { .. } => "unknown-name",
            Error::Motion { .. } => "motion",
            Error::Pose { .. } => "pose",
            Error::Checkpoint(_) => "checkpoint",
            Error::Fit(_) => "fit",
            Error::Study { .. } => "study",
            Error::Clock(_) => "clock",
            Error::Cancelled => "cancelled",
            Error::OpenScan { .. } => "open-scan",
        }
    }

    /// A parameter error: `name` (the library's name of the parameter) must be `expected`, and
    /// was `value`.
    pub fn parameter(name: &str, value: impl std::fmt::Display, expected: impl Into<String>) -> Self {
        Error::Parameter { name: name.to_string(), value: value.to_string(), expected: expected.into() }
    }

    /// The message with the parameter's name spelled by `spell` (a command-line flag, a
    /// keyword argument); other errors as they are.
    pub fn spelled(&self, spell: &dyn Fn(&str) -> String) -> String {
        match self {
            Error::Parameter { name, value, expected } => format!("{} must be {expected}, got {value}", spell(name)),
            Error::SizeUnknown { mesh, one_stone } => format!("{mesh}: {}", size_unknown(*one_stone, spell)),
            e => e.to_string(),
        }
    }

    /// An unknown name: `given` is not one of `allowed` (names of a `what`).
    pub fn unknown(what: &'static str, given: &str, allowed: &[&str]) -> Self {
        Error::Unknown { what, given: given.to_string(), allowed: allowed.iter().map(|s| s.to_string()).collect() }
    }

    /// A motion that cannot drive a run: `name` and what is wrong with it.
    pub fn motion(name: impl Into<String>, what: impl Into<String>) -> Self {
        Error::Motion { name: name.into(), what: what.into() }
    }

    /// An in-memory open-scan error ([`Error::OpenScan`]).
    pub fn open_scan(problem: ScanProblem, what: impl Into<String>) -> Self {
        Error::OpenScan { path: MEMORY.into(), problem, what: what.into() }
    }

    /// Shorthand for an in-memory failed internal check.
    pub fn check(what: impl Into<String>) -> Self {
        Error::Check { path: MEMORY.into(), what: what.into() }
    }
}

/// What [`Error::SizeUnknown`] says, its parameters spelled by `spell`: the length unit, and for
/// one stone its size as an alternative.
fn size_unknown(one_stone: bool, spell: &dyn Fn(&str) -> String) -> String {
    let or_size = match one_stone {
        true => format!(" or {} (R_max in metres)", spell("size")),
        false => String::new(),
    };
    format!(
        "its length unit is not known, and the result depends on the stone's real size (the rolling resistance \
         relative to R_max; under shaking, the real frequencies of the motion): give {} (mm, cm, m, km, in or \
         metres per mesh unit){or_size}",
        spell("length_unit"),
    )
}

fn near_text(near: &Option<[f64; 3]>) -> String {
    near.map_or(String::new(), |[x, y, z]| format!(" near ({x:.6e}, {y:.6e}, {z:.6e})"))
}

/// Placeholder path of meshes that live only in memory.
pub const MEMORY: &str = "<memory>";
