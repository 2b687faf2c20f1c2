//! penumbra-image
