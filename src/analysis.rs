//! The static pipeline.
