//! The convex solve against the grid search on the RICSAC problems lives in the integration
//! tests; here, the pieces.
