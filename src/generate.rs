//! Seeded shape generators.
