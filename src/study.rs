//! Field studies and synthetic hand experiments (being written).
