//! GGX / Trowbridge–Reitz microfacet distribution with Smith
//! masking–shadowing and visible-normal sampling.
