//! Statistics of runs and samples: binomial intervals, goodness of fit, moments, trend lines and
//! grids.
//!
//! One file a concept: [`intervals`] of a rate, [`hypothesis`] tests of counts, [`summary`] of a
//! sample, [`trends`] and grids, [`forecasts`] and their scores; everything is re-exported here.

pub mod forecasts;
pub mod hypothesis;
pub mod intervals;
pub mod summary;
pub mod trends;

pub use forecasts::{
    binomial_log_likelihood, ensemble_brier, forecast_scores, logistic, mann_whitney_auc, oracle_brier, Forecast,
    ForecastScores,
};
pub use hypothesis::{
    binomial_at_least, chi_square, chi_square_homogeneity, chi_square_tail, kl_divergence, stuart_maxwell,
};
pub use intervals::{rate_with_wilson, wilson};
pub use summary::{
    five_numbers, mean, median_range, min_max, nonnegative_range, quantile, root_mean_square, sample_sd,
};
pub use trends::{log_fit, log_grid, upward_crossing, GridSize, LogFit};
