//! The names a program over the library uses most: `use rocking_stones::prelude::*;`.
//!
//! The static analysis ([`Analysis`] with its [`Options`], shapes from [`generate`]), the
//! prepared stone and its surface pair ([`Stone`], [`Surface`]), drops ([`Preset`],
//! [`DropParams`], one release [`launch`] and its [`DropOutcome`], a Monte Carlo run
//! [`RunHeader`] → [`run_and_summarize`] → [`DropReport`], the [`CertificateMode`] that ends
//! drops early, the engine's [`Flight`] and [`REFERENCE_DT`]), random streams ([`item_rng`]),
//! vectors ([`Vec3`], [`Point3`]) and the house style's plots ([`Chart`], [`Figure`], [`Axis`],
//! [`Mark`], [`Marker`], [`RGBColor`], [`series_color`], [`colors`]). Everything else is imported
//! from its module. The library's `Result` is not here, so that a program's own (`anyhow`, say)
//! does not clash with it.

pub use crate::analysis::{Analysis, Options};
pub use crate::dynamics::certificate::CertificateMode;
pub use crate::dynamics::drops::launch::{launch, DropOutcome};
pub use crate::dynamics::drops::montecarlo::{run_and_summarize, DropReport, RunHeader, DEFAULT_BATCH};
pub use crate::dynamics::drops::params::{DropParams, Preset};
pub use crate::dynamics::engine::params::{Flight, REFERENCE_DT};
pub use crate::dynamics::stone::Stone;
pub use crate::dynamics::surface::Surface;
pub use crate::plot::{colors, series_color, Axis, Chart, Figure, Mark, Marker, RGBColor};
pub use crate::rng::item_rng;
pub use crate::{generate, Point3, Vec3};
