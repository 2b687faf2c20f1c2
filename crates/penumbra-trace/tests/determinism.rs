//! The same seed gives bit-identical images for any thread count.

use penumbra_image::{ToneMapping, write_image};
use penumbra_scene::IntegratorKind;
use penumbra_trace::{RenderOptions, render};

#[test]
fn same_seed_same_exr_with_one_and_two_threads() {
    let scene = penumbra_scene::builtin::cornell_box();
    let mut settings = scene.settings.clone();
    settings.width = 64;
    settings.height = 48;
    settings.spp = 9;
    settings.integrator = IntegratorKind::Path;
    let dir = tempfile::tempdir().unwrap();
    let mut files = Vec::new();
    for threads in [1, 2] {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        let out = pool.install(|| {
            render(
                &scene,
                &settings,
                &RenderOptions {
                    aovs: true,
                    ..Default::default()
                },
            )
            .unwrap()
        });
        let path = dir.path().join(format!("t{threads}.exr"));
        let aovs: Vec<(&str, &penumbra_image::Image)> =
            out.aovs.iter().map(|(n, i)| (n.as_str(), i)).collect();
        write_image(&path, &out.image, &aovs, &ToneMapping::default()).unwrap();
        files.push(std::fs::read(&path).unwrap());
    }
    assert_eq!(files[0], files[1]);
    // A different seed gives a different image.
    settings.seed += 1;
    let other = render(&scene, &settings, &RenderOptions::default()).unwrap();
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap();
    settings.seed -= 1;
    let same = pool.install(|| render(&scene, &settings, &RenderOptions::default()).unwrap());
    assert_ne!(other.image, same.image);
}
