pub mod analyze;
pub mod generate;
pub mod planar;
