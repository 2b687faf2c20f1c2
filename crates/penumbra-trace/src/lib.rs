//! penumbra-trace
