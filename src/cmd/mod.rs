pub mod analyze;
pub mod drop;
pub mod generate;
pub mod planar;
