//! The convergence record of an iterative bake (radiosity): one row per
//! iteration, written as CSV and plotted beside the maps.

/// The state after one iteration.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ConvergenceStep {
    /// 0 for the state after the lights outside the patches shot.
    pub iteration: u32,
    /// The patch that shot in this iteration (`None` for iteration 0).
    pub shooter: Option<u32>,
    /// Unshot power left in the patches [W] (luminance-weighted RGB).
    pub unshot_power: f64,
    /// `unshot_power` over the power emitted into the scene.
    pub unshot_fraction: f64,
    /// Time since the start of the solve [s].
    pub seconds: f64,
}
