//! A render is a pure function of scene, parameters and seed: the same bytes with 1 and 2
//! threads, for both drivers (pixel-parallel and light-path-parallel).

mod common;

use caustica_render::IntegratorKind;

fn bytes(img: &caustica_core::image_io::Image) -> Vec<u32> {
    img.data.iter().flat_map(|p| p.map(f32::to_bits)).collect()
}

#[test]
fn same_seed_same_bytes_for_any_thread_count() {
    let scene = common::diffuse_box(24, 16);
    for kind in [IntegratorKind::Path, IntegratorKind::LightTrace] {
        let run = |threads: usize, seed: u64| {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            pool.install(|| common::render_image(&scene, kind, 64, seed))
        };
        let a = run(1, 7);
        let b = run(2, 7);
        let c = run(2, 8);
        assert_eq!(bytes(&a), bytes(&b), "{kind:?}: 1 and 2 threads differ");
        assert_ne!(bytes(&a), bytes(&c), "{kind:?}: the seed has no effect");
    }
}
