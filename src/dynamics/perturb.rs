//! Perturbation robustness of stable micro-equilibria (being written).
