pub mod bake;
pub mod bench;
pub mod bench_bake;
pub mod bench_raster;
pub mod compare;
pub mod info;
pub mod render;
pub mod study;
