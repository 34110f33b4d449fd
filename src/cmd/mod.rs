pub mod analyze;
pub mod drop;
pub mod generate;
pub mod perturb;
pub mod planar;
pub mod shake;
pub mod study;
