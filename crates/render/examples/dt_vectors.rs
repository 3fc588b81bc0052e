//! Seed 003 fig. 10: the time differentials `D_t x` of caustic photons projected on the plane
//! they land on, drawn as arrows from each landing `x` to `x + D_t x` (top view, x to the right,
//! z down, as the built-in scenes' cameras see the floor).
//!
//!     cargo run --profile fast -p caustica-render --example dt_vectors -- SCENE [PATHS] [EXPOSURE] > out.svg
//!
//! SCENE is a built-in animated scene (`moving-wave`, `rotating-rod`); PATHS light paths are
//! traced (default 400) at the frame instant with the shutter's length EXPOSURE frames (default
//! 4: a long exposure makes the vectors visible, as in the figure). Used by bench/temporal.sh.

use caustica_core::Vec3;
use caustica_core::sampling::{Sampler, SamplerKind};
use caustica_render::photon::differential::{Landing, LandingTracer, TEMPORAL_PARAMS, unit_budget};
use caustica_render::{FootprintSettings, PathLimits, RenderStats, Smoothing};
use caustica_scene::Shutter;
use std::fmt::Write;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    let name = args.get(1).map_or("moving-wave", String::as_str);
    let paths: u64 = args.get(2).map_or(Ok(400), |s| s.parse())?;
    let exposure: f32 = args.get(3).map_or(Ok(4.0), |s| s.parse())?;
    let mut b = caustica_loader::builtin_scene(name)
        .ok_or_else(|| format!("'{name}' is not a built-in scene"))?;
    b.set_shutter(Shutter::new(b.shutter().open, exposure)?);
    let scene = b.build()?;
    if !scene.has_motion() {
        return Err(format!("'{name}' does not move").into());
    }
    let settings = FootprintSettings {
        temporal: true,
        ..Default::default()
    };
    let tracer =
        LandingTracer::new(&scene, &unit_budget(Smoothing::ONE)).with_time(&settings, &scene);
    let limits = PathLimits {
        max_depth: 16,
        ..PathLimits::default()
    };
    let mut sampler = Sampler::new(SamplerKind::Independent, 7);
    let mut stats = RenderStats::default();
    let mut landings: Vec<Landing<TEMPORAL_PARAMS>> = Vec::new();
    // Enough light paths to find PATHS caustic landings (most paths of a directional light miss
    // the specular object), at most 1000 × PATHS.
    let mut path = 0;
    while (landings.len() as u64) < paths && path < 1000 * paths {
        sampler.start_path(1, path);
        tracer.trace::<TEMPORAL_PARAMS>(&mut sampler, &limits, &mut landings, &mut stats);
        path += 1;
    }
    let arrows: Vec<(Vec3, Vec3)> = landings
        .iter()
        .filter_map(|l| l.dp.map(|d| (l.p, d[TEMPORAL_PARAMS - 1])))
        .filter(|(p, d)| p.is_finite() && d.is_finite())
        .collect();
    // The camera's view of the floor: the square its field of view covers at y = 0.
    let cam = &scene.camera;
    let eye = cam.to_world.transform_point3(Vec3::ZERO);
    let half = eye.y * (0.5 * cam.fov_deg.to_radians()).tan();
    let (x0, z0) = (eye.x - half, eye.z - half);
    let px = 600.0 / (2.0 * half);
    let to_svg = |p: Vec3| ((p.x - x0) * px, (p.z - z0) * px);
    let mut svg = String::new();
    writeln!(
        svg,
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"600\" height=\"640\" viewBox=\"0 0 600 640\">\n\
         <defs><marker id=\"a\" markerWidth=\"6\" markerHeight=\"6\" refX=\"5\" refY=\"3\" orient=\"auto\">\
         <path d=\"M0,0 L6,3 L0,6 z\" fill=\"#1f5fd6\"/></marker></defs>\n\
         <rect width=\"600\" height=\"600\" fill=\"white\" stroke=\"#888\"/>"
    )?;
    for (p, d) in &arrows {
        let (ax, ay) = to_svg(*p);
        let (bx, by) = to_svg(*p + *d);
        writeln!(
            svg,
            "<circle cx=\"{ax:.1}\" cy=\"{ay:.1}\" r=\"1.2\" fill=\"black\"/>\
             <line x1=\"{ax:.1}\" y1=\"{ay:.1}\" x2=\"{bx:.1}\" y2=\"{by:.1}\" stroke=\"#1f5fd6\" \
             stroke-width=\"0.8\" marker-end=\"url(#a)\"/>"
        )?;
    }
    let mean = arrows.iter().map(|(_, d)| d.length()).sum::<f32>() / arrows.len().max(1) as f32;
    writeln!(
        svg,
        "<text x=\"8\" y=\"625\" font-family=\"sans-serif\" font-size=\"13\">{name}: {} caustic \
         photons at frame {}, exposure {exposure} frames; arrows x → x + D_t x (mean |D_t x| \
         {mean:.3} m); view {:.2} m wide</text>\n</svg>",
        arrows.len(),
        scene.shutter.open,
        2.0 * half
    )?;
    print!("{svg}");
    Ok(())
}
