use super::*;
use caustica_core::Spectrum;
use caustica_scene::camera::FovAxis;
use caustica_scene::light::Light;
use caustica_scene::material::{Material, conductor_preset};
use caustica_scene::scene::FilterKind;
use caustica_scene::shape::ShapeGeometry;
use caustica_scene::texture::Texture;

const CAM: &str = r#"<sensor type="perspective"><float name="fov" value="40"/>
<film type="hdrfilm"><integer name="width" value="8"/><integer name="height" value="8"/></film></sensor>"#;

fn path() -> PathBuf {
    PathBuf::from("/virtual/dir/scene.xml")
}

fn parse(body: &str) -> Result<SceneBuilder, LoadError> {
    parse_defs(body, &[])
}

fn parse_defs(body: &str, defs: &[(&str, &str)]) -> Result<SceneBuilder, LoadError> {
    let text = format!("<scene version=\"3.0.0\">\n{body}\n</scene>\n");
    let defs: Vec<(String, String)> = defs
        .iter()
        .map(|(a, b)| (a.to_string(), b.to_string()))
        .collect();
    parse_mitsuba(&text, &path(), &defs)
}

/// Expects a parse error at `line` (1-based, the `<scene>` tag is line 1) and `column`
/// (`None`: any column) whose message contains every word of `words`.
fn expect_err(
    r: Result<SceneBuilder, LoadError>,
    line: usize,
    column: Option<usize>,
    words: &[&str],
) {
    match r {
        Err(LoadError::Parse {
            line: l,
            column: c,
            message,
            ..
        }) => {
            assert_eq!(l, line, "line of: {message}");
            if let Some(col) = column {
                assert_eq!(c, col, "column of: {message}");
            }
            for w in words {
                assert!(message.contains(w), "'{w}' not in: {message}");
            }
        }
        Err(e) => panic!("expected a parse error, got {e}"),
        Ok(_) => panic!("expected a parse error"),
    }
}

fn only_material(b: &SceneBuilder) -> &Material {
    b.materials().last().unwrap()
}

fn sphere_centre(b: &SceneBuilder, i: usize) -> Vec3 {
    match &b.shapes()[i].geometry {
        ShapeGeometry::Sphere(s) => s.center,
        _ => panic!("not a sphere"),
    }
}

#[test]
fn substitution_defaults_and_defines() {
    let body = r#"<default name="r" value="0.25"/>
<default name="g" value="0.5"/>
<bsdf type="diffuse" id="a"><rgb name="reflectance" value="$r, $g $r"/></bsdf>"#;
    let b = parse(body).unwrap();
    let Material::Diffuse {
        reflectance: Texture::Constant(c),
    } = only_material(&b)
    else {
        panic!()
    };
    assert_eq!(c.to_rgb(), [0.25, 0.5, 0.25]);
    // A define overrides the default; the other default still applies.
    let b = parse_defs(body, &[("r", "0.125")]).unwrap();
    let Material::Diffuse {
        reflectance: Texture::Constant(c),
    } = only_material(&b)
    else {
        panic!()
    };
    assert_eq!(c.to_rgb(), [0.125, 0.5, 0.125]);
    // An undefined parameter is an error at the attribute value.
    expect_err(
        parse(r#"<bsdf type="diffuse"><float name="reflectance" value="$nope"/></bsdf>"#),
        2,
        Some(55),
        &["$nope"],
    );
}

#[test]
fn references_resolve_including_nested_ones() {
    let body = r#"<bsdf type="conductor" id="gold"><string name="material" value="Au"/></bsdf>
<bsdf type="twosided" id="two"><ref id="gold"/></bsdf>
<shape type="sphere"><ref id="gold"/></shape>
<shape type="sphere"><ref name="bsdf" id="two"/></shape>"#;
    let b = parse(body).unwrap();
    let (eta, k) = conductor_preset("Au").unwrap();
    assert_eq!(b.materials().len(), 2);
    for s in b.shapes() {
        let m = &b.materials()[s.material as usize];
        assert!(matches!(m, Material::Conductor { eta: e, k: kk, .. } if *e == eta && *kk == k));
    }
    assert_eq!(b.material_names(), ["gold", "two"]);
    assert_eq!(b.shapes()[0].material, 0);
    assert_eq!(b.shapes()[1].material, 1);
    expect_err(
        parse(r#"<shape type="sphere"><ref id="missing"/></shape>"#),
        2,
        Some(31),
        &["missing"],
    );
    expect_err(
        parse(r#"<bsdf type="diffuse" id="a"/><bsdf type="diffuse" id="a"/>"#),
        2,
        Some(55),
        &["duplicate"],
    );
}

#[test]
fn transforms_compose_in_mitsuba_order() {
    // Sphere at the origin moved to (1, 0, 0), then rotated 90° about z → (0, 1, 0).
    let tr = r#"<translate x="1"/><rotate z="1" angle="90"/>"#;
    // Rotated first (origin stays), then moved → (1, 0, 0).
    let rt = r#"<rotate z="1" angle="90"/><translate value="1 0 0"/>"#;
    // Scale 2 then translate: centre (0.5,0,0) → (1,0,0) → (1,0,3); radius 0.5 → 1.
    let st = r#"<scale value="2"/><translate x="0" y="0" z="3"/>"#;
    let body = format!(
        r#"<shape type="sphere"><transform name="to_world">{tr}</transform></shape>
<shape type="sphere"><transform name="to_world">{rt}</transform></shape>
<shape type="sphere"><point name="center" x="0.5" y="0" z="0"/><float name="radius" value="0.5"/>
<transform name="to_world">{st}</transform></shape>
<shape type="sphere"><transform name="to_world"><matrix value="1 0 0 4  0 1 0 5  0 0 1 6  0 0 0 1"/></transform></shape>"#
    );
    let b = parse(&body).unwrap();
    assert!(sphere_centre(&b, 0).abs_diff_eq(Vec3::new(0.0, 1.0, 0.0), 1e-6));
    assert!(sphere_centre(&b, 1).abs_diff_eq(Vec3::new(1.0, 0.0, 0.0), 1e-6));
    assert!(sphere_centre(&b, 2).abs_diff_eq(Vec3::new(1.0, 0.0, 3.0), 1e-6));
    let ShapeGeometry::Sphere(s) = &b.shapes()[2].geometry else {
        panic!()
    };
    assert!((s.radius - 1.0).abs() < 1e-6);
    // Row-major matrix: the last column is the translation.
    assert_eq!(sphere_centre(&b, 3), Vec3::new(4.0, 5.0, 6.0));
    // Non-uniform scale on a sphere is an error.
    expect_err(
        parse(
            r#"<shape type="sphere"><transform name="to_world"><scale x="2"/></transform></shape>"#,
        ),
        2,
        Some(1),
        &["uniform"],
    );
}

#[test]
fn bsdfs_convert() {
    let body = r#"<bsdf type="diffuse" id="d"><float name="reflectance" value="0.3"/></bsdf>
<bsdf type="dielectric" id="water"><string name="int_ior" value="water"/><string name="ext_ior" value="vacuum"/></bsdf>
<bsdf type="dielectric" id="bk7"/>
<bsdf type="dielectric" id="num"><float name="int_ior" value="1.6"/><float name="ext_ior" value="1.2"/></bsdf>
<bsdf type="roughdielectric" id="rd"><float name="alpha" value="0.2"/><string name="distribution" value="ggx"/></bsdf>
<bsdf type="thindielectric" id="thin"/>
<bsdf type="conductor" id="mirror"/>
<bsdf type="conductor" id="explicit"><rgb name="eta" value="0.2 0.3 0.4"/><rgb name="k" value="3 2 1"/></bsdf>
<bsdf type="roughconductor" id="rc"><string name="material" value="Cu"/><float name="alpha" value="0.3"/><spectrum name="specular_reflectance" value="0.5"/></bsdf>
<bsdf type="twosided" id="ts"><bsdf type="diffuse"><rgb name="reflectance" value="0.1, 0.2, 0.3"/></bsdf></bsdf>
<bsdf type="plastic" id="pl"><rgb name="diffuse_reflectance" value="0.5 0.5 0.5"/></bsdf>"#;
    let b = parse(body).unwrap();
    let m = |n: &str| &b.materials()[b.material_index(n).unwrap() as usize];
    assert!(
        matches!(m("d"), Material::Diffuse { reflectance: Texture::Constant(c) } if c.to_rgb() == [0.3; 3])
    );
    assert!(matches!(m("water"), Material::Dielectric { ior, .. } if *ior == 1.333));
    assert!(
        matches!(m("bk7"), Material::Dielectric { ior, .. } if (*ior - 1.5046 / 1.000277).abs() < 1e-6)
    );
    assert!(
        matches!(m("num"), Material::Dielectric { ior, .. } if (*ior - 1.6 / 1.2).abs() < 1e-6)
    );
    assert!(
        matches!(m("rd"), Material::RoughDielectric { ior, alpha, .. } if *alpha == 0.2 && (*ior - 1.5046 / 1.000277).abs() < 1e-6)
    );
    assert!(matches!(m("thin"), Material::Dielectric { ior, .. } if *ior == 1.0));
    assert!(
        matches!(m("mirror"), Material::Mirror { reflectance } if *reflectance == Spectrum::ONE)
    );
    assert!(matches!(m("explicit"), Material::Conductor { eta, k, .. }
        if eta.to_rgb() == [0.2, 0.3, 0.4] && k.to_rgb() == [3.0, 2.0, 1.0]));
    let (eta_cu, k_cu) = conductor_preset("Cu").unwrap();
    assert!(
        matches!(m("rc"), Material::RoughConductor { eta, k, alpha, specular }
        if *eta == eta_cu && *k == k_cu && *alpha == 0.3 && specular.to_rgb() == [0.5; 3])
    );
    assert!(
        matches!(m("ts"), Material::Diffuse { reflectance: Texture::Constant(c) } if c.to_rgb() == [0.1, 0.2, 0.3])
    );
    // Plastic: F0 of ior 1.49/1.000277 ≈ 0.0386 (hand-computed: ((1.4896-1)/(2.4896))² = 0.03868).
    let Material::Phong {
        diffuse: Texture::Constant(kd),
        specular,
        ..
    } = m("pl")
    else {
        panic!()
    };
    assert!(
        (specular.to_rgb()[0] - 0.03868).abs() < 2e-4,
        "{specular:?}"
    );
    assert!((kd.to_rgb()[0] - 0.5 * (1.0 - 0.03868)).abs() < 2e-4);
    // Approximations are reported in one warning naming lines.
    let w = b.pending_warnings();
    let approx: Vec<_> = w.iter().filter(|w| w.contains("approximated")).collect();
    assert_eq!(approx.len(), 1, "{w:?}");
    assert!(
        approx[0].contains("thindielectric") && approx[0].contains("scene.xml:7"),
        "{w:?}"
    );
    assert!(
        approx[0].contains("Phong") && approx[0].contains("scene.xml:12"),
        "{w:?}"
    );
    // Unknown names are errors at the attribute value.
    expect_err(
        parse(r#"<bsdf type="dielectric"><string name="int_ior" value="unobtainium"/></bsdf>"#),
        2,
        Some(55),
        &["unobtainium"],
    );
    expect_err(
        parse(r#"<bsdf type="conductor"><string name="material" value="Xx"/></bsdf>"#),
        2,
        Some(55),
        &["Xx"],
    );
    expect_err(parse(r#"<bsdf type="velvet"/>"#), 2, Some(13), &["velvet"]);
    // Albedo above one is rejected with the element's position.
    expect_err(
        parse(r#"<bsdf type="diffuse"><float name="reflectance" value="1.5"/></bsdf>"#),
        2,
        Some(1),
        &["reflectance"],
    );
}

#[test]
fn shapes_convert() {
    let body = r#"<shape type="disk"><transform name="to_world"><scale value="2"/><rotate x="1" angle="90"/><translate y="1"/></transform>
  <boolean name="flip_normals" value="true"/></shape>
<shape type="rectangle"><transform name="to_world"><scale x="2" y="3"/></transform>
  <emitter type="area"><rgb name="radiance" value="1 2 3"/></emitter></shape>
<shape type="cube"/>
<shape type="cylinder"><float name="radius" value="0.5"/><point name="p1" x="0" y="2" z="0"/></shape>"#;
    let b = parse(body).unwrap();
    assert_eq!(b.shape_count(), 4);
    // Disk: +z rotated 90° about x → −y... then flipped → +y; radius 2 at (0, 1, 0).
    let ShapeGeometry::Disk(d) = &b.shapes()[0].geometry else {
        panic!()
    };
    assert!(d.center.abs_diff_eq(Vec3::new(0.0, 1.0, 0.0), 1e-6));
    assert!(d.normal.abs_diff_eq(Vec3::Y, 1e-6), "{:?}", d.normal);
    assert!((d.radius - 2.0).abs() < 1e-6);
    // Rectangle 4 × 6 emitting (1, 2, 3): power π·A·L.
    let ShapeGeometry::Mesh(r) = &b.shapes()[1].geometry else {
        panic!()
    };
    assert!((r.triangle_area(0) + r.triangle_area(1) - 24.0).abs() < 1e-4);
    assert_eq!(b.lights().len(), 1);
    let p = b.lights()[0].power().to_rgb();
    let pi = std::f32::consts::PI;
    for (c, l) in p.iter().zip([1.0, 2.0, 3.0]) {
        assert!((c - pi * 24.0 * l).abs() < 1e-3 * c, "{p:?}");
    }
    // Cube: area 6 · 4.
    let ShapeGeometry::Mesh(c) = &b.shapes()[2].geometry else {
        panic!()
    };
    let area: f32 = (0..12).map(|i| c.triangle_area(i)).sum();
    assert!((area - 24.0).abs() < 1e-4);
    // Cylinder along y, radius 0.5, length 2: lateral area 2π·0.5·2 = 2π within tessellation
    // error (64 segments: factor sin(π/64)/(π/64) ≈ 0.9996).
    let ShapeGeometry::Mesh(cy) = &b.shapes()[3].geometry else {
        panic!()
    };
    let area: f32 = (0..cy.indices.len()).map(|i| cy.triangle_area(i)).sum();
    assert!((area - 2.0 * pi).abs() < 2e-3 * 2.0 * pi, "{area}");
    assert!(cy.positions.iter().all(|p| p.y > -1e-6 && p.y < 2.0 + 1e-6));
    assert!(
        cy.positions
            .iter()
            .all(|p| ((p.x * p.x + p.z * p.z).sqrt() - 0.5).abs() < 1e-5)
    );
    // Unknown shape type, missing mesh.
    expect_err(parse(r#"<shape type="teapot"/>"#), 2, Some(14), &["teapot"]);
    match parse(r#"<shape type="obj"><string name="filename" value="meshes/none.obj"/></shape>"#) {
        Err(LoadError::File { path, .. }) => assert!(path.ends_with("dir/meshes/none.obj")),
        Err(e) => panic!("{e}"),
        Ok(_) => panic!("missing mesh accepted"),
    }
    // An OBJ mesh with face_normals drops its vertex normals and is transformed.
    let dir = std::env::temp_dir().join(format!("caustica-mitsuba-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(
        dir.join("tri.obj"),
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2//1 3//1\n",
    )
    .unwrap();
    let text = r#"<scene version="3.0.0"><shape type="obj"><string name="filename" value="tri.obj"/>
<boolean name="face_normals" value="true"/><transform name="to_world"><translate z="2"/></transform></shape></scene>"#;
    let b = parse_mitsuba(text, &dir.join("s.xml"), &[]).unwrap();
    let ShapeGeometry::Mesh(m) = &b.shapes()[0].geometry else {
        panic!()
    };
    assert!(m.normals.is_none());
    assert!(m.positions.iter().all(|p| p.z == 2.0));
}

#[test]
fn emitters_convert() {
    let body = r#"<emitter type="point"><rgb name="intensity" value="1 2 3"/><point name="position" x="0" y="4" z="0"/></emitter>
<emitter type="point"><transform name="to_world"><translate x="5"/></transform></emitter>
<emitter type="spot"><float name="intensity" value="7"/><float name="cutoff_angle" value="40"/>
  <transform name="to_world"><lookat origin="0 3 0" target="0 0 0" up="0 0 1"/></transform></emitter>
<emitter type="directional"><vector name="direction" value="0, -2, 0"/><spectrum name="irradiance" value="3"/></emitter>
<emitter type="constant"><rgb name="radiance" value="0.5 0.5 0.5"/></emitter>"#;
    let b = parse(body).unwrap();
    let l = b.lights();
    assert_eq!(l.len(), 5);
    let Light::Point(p) = &l[0] else { panic!() };
    assert_eq!(p.position, Vec3::new(0.0, 4.0, 0.0));
    assert_eq!(p.intensity.to_rgb(), [1.0, 2.0, 3.0]);
    let Light::Point(p) = &l[1] else { panic!() };
    assert_eq!(p.position, Vec3::new(5.0, 0.0, 0.0));
    assert_eq!(p.intensity, Spectrum::ONE);
    let Light::Spot(s) = &l[2] else { panic!() };
    assert!(s.position.abs_diff_eq(Vec3::new(0.0, 3.0, 0.0), 1e-6));
    assert!(s.frame.n.abs_diff_eq(-Vec3::Y, 1e-6));
    assert!((s.cutoff_angle - 40f32.to_radians()).abs() < 1e-6);
    assert!((s.beam_width - 30f32.to_radians()).abs() < 1e-6);
    let Light::Directional(dl) = &l[3] else {
        panic!()
    };
    assert!(dl.direction.abs_diff_eq(-Vec3::Y, 1e-6));
    assert!(matches!(&l[4], Light::Environment(_)));
    expect_err(
        parse(r#"<emitter type="envmap"/>"#),
        2,
        Some(16),
        &["envmap"],
    );
    expect_err(
        parse(r#"<shape type="sphere"><emitter type="point"/></shape>"#),
        2,
        Some(37),
        &["point"],
    );
}

#[test]
fn directionalarea_disks_become_beam_lights() {
    // A disk of radius 0.02 m at (0, 0.99, 0) facing down (+z rotated 90° about x), a second
    // one flipped (facing up) in a medium, with a BSDF.
    let body = r#"<medium type="homogeneous" id="fog"><float name="sigma_t" value="0.5"/></medium>
<shape type="disk">
  <transform name="to_world"><scale value="0.02"/><rotate x="1" angle="90"/><translate y="0.99"/></transform>
  <emitter type="directionalarea"><rgb name="radiance" value="1000, 500, 250"/></emitter>
</shape>
<shape type="disk"><boolean name="flip_normals" value="true"/>
  <transform name="to_world"><scale value="2"/><rotate x="1" angle="90"/><translate x="5"/></transform>
  <bsdf type="diffuse"/><ref name="exterior" id="fog"/>
  <emitter type="directionalarea"/>
</shape>"#;
    let b = parse(&format!("{body}\n{CAM}")).unwrap();
    assert_eq!(b.shape_count(), 0, "the apertures are not surfaces");
    let [Light::Beam(l), Light::Beam(m)] = b.lights() else {
        panic!("two beams: {:?}", b.lights())
    };
    assert!(l.center.abs_diff_eq(Vec3::new(0.0, 0.99, 0.0), 1e-6));
    assert!(
        l.direction().abs_diff_eq(-Vec3::Y, 1e-6),
        "{}",
        l.direction()
    );
    assert!((l.radius - 0.02).abs() < 1e-7);
    // radiance is the irradiance across the beam: power = radiance × π r² (W).
    assert_eq!(l.irradiance.to_rgb(), [1000.0, 500.0, 250.0]);
    let pi = std::f32::consts::PI;
    let p = b.lights()[0].power().to_rgb();
    for (c, e) in p.iter().zip([1000.0, 500.0, 250.0]) {
        assert!((c - e * pi * 4e-4).abs() < 1e-5 * c, "{p:?}");
    }
    // flip_normals reverses the beam; default radiance 1; the exterior medium is the light's.
    assert!(m.direction().abs_diff_eq(Vec3::Y, 1e-6));
    assert!((m.radius - 2.0).abs() < 1e-6 && m.irradiance == Spectrum::ONE);
    let w = b.pending_warnings();
    assert!(
        w.len() == 1 && w[0].contains("BSDF of a directionalarea disk") && w[0].contains(":7"),
        "{w:?}"
    );
    let scene = b.build().unwrap();
    assert_eq!(scene.light_media, vec![NONE, 0]);

    // Anything but a disk, or at the top level: errors naming the line (and column of the
    // emitter's type).
    expect_err(
        parse(
            r#"<shape type="rectangle">
<emitter type="directionalarea"/></shape>"#,
        ),
        3,
        Some(16),
        &["directionalarea", "disk", "rectangle"],
    );
    expect_err(
        parse(r#"<shape type="sphere"><emitter type="directionalarea"/></shape>"#),
        2,
        Some(37),
        &["directionalarea", "disk", "sphere"],
    );
    expect_err(
        parse(r#"<emitter type="directionalarea"/>"#),
        2,
        Some(16),
        &["directionalarea", "inside a <shape>"],
    );
    expect_err(
        parse(
            r#"<shape type="disk"><emitter type="directionalarea"><rgb name="radiance" value="-1"/></emitter></shape>"#,
        ),
        2,
        None,
        &["directionalarea", "non-negative"],
    );
}

#[test]
fn sensor_film_sampler_integrator() {
    let body = r#"<integrator type="ptracer"><integer name="max_depth" value="5"/></integrator>
<sensor type="perspective"><float name="fov" value="30"/><string name="fov_axis" value="y"/>
  <float name="near_clip" value="0.1"/>
  <transform name="to_world"><lookat origin="1, 2, 3" target="1, 2, -1" up="0, 1, 0"/></transform>
  <sampler type="independent"><integer name="sample_count" value="16"/></sampler>
  <film type="hdrfilm"><integer name="width" value="64"/><integer name="height" value="32"/>
    <rfilter type="gaussian"><float name="stddev" value="0.25"/></rfilter></film></sensor>"#;
    let b = parse(body).unwrap();
    let c = b.camera().unwrap();
    assert_eq!(
        (c.width, c.height, c.fov_deg, c.fov_axis),
        (64, 32, 30.0, FovAxis::Y)
    );
    assert_eq!(c.near_clip, 0.1);
    // Looking down −z: camera +x (image left) is world −x.
    assert!(Vec3::from(c.to_world.matrix3.x_axis).abs_diff_eq(-Vec3::X, 1e-6));
    assert!(Vec3::from(c.to_world.matrix3.z_axis).abs_diff_eq(-Vec3::Z, 1e-6));
    assert_eq!(c.position(), Vec3::new(1.0, 2.0, 3.0));
    assert_eq!(b.settings.spp, Some(16));
    assert_eq!(b.settings.max_depth, Some(5));
    assert_eq!(b.settings.integrator.as_deref(), Some("ptracer"));
    assert_eq!(
        b.settings.filter,
        FilterKind::Gaussian {
            stddev: 0.25,
            radius: 1.0
        }
    );
    // Diagonal fov converts exactly: 4:3 image, diagonal 90° → tan(x/2) = 0.8.
    let body = r#"<sensor type="perspective"><float name="fov" value="90"/><string name="fov_axis" value="diagonal"/>
<film type="hdrfilm"><integer name="width" value="400"/><integer name="height" value="300"/></film></sensor>"#;
    let b = parse(body).unwrap();
    let c = b.camera().unwrap();
    assert!((c.fov_deg - 2.0 * 0.8f32.atan().to_degrees()).abs() < 1e-4);
    expect_err(
        parse(
            r#"<sensor type="perspective"><float name="fov" value="30"/><string name="fov_axis" value="z"/></sensor>"#,
        ),
        2,
        Some(89),
        &["fov_axis", "'z'"],
    );
}

#[test]
fn cornell_box_matches_builtin() {
    let file = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/mitsuba/cornell-box.xml");
    let b = load_mitsuba(&file, &[]).unwrap();
    let reference = crate::builtin_scene("cornell-box").unwrap();
    assert_eq!(b.shape_count(), reference.shape_count());
    assert_eq!(b.lights().len(), 1);
    assert_eq!(b.settings.spp, Some(64));
    assert_eq!(b.settings.max_depth, Some(8));
    assert_eq!(
        b.settings.filter,
        FilterKind::Gaussian {
            stddev: 0.5,
            radius: 2.0
        }
    );
    assert!(
        b.pending_warnings().is_empty(),
        "{:?}",
        b.pending_warnings()
    );
    let (c, rc) = (b.camera().unwrap(), reference.camera().unwrap());
    assert!(c.to_world.abs_diff_eq(rc.to_world, 1e-6));
    assert_eq!(
        (c.width, c.height, c.fov_deg),
        (rc.width, rc.height, rc.fov_deg)
    );
    assert_eq!(c.fov_axis, FovAxis::Smaller);
    // Same geometry, shape by shape (same order as the built-in scene).
    for (s, r) in b.shapes().iter().zip(reference.shapes()) {
        let (ShapeGeometry::Mesh(m), ShapeGeometry::Mesh(rm)) = (&s.geometry, &r.geometry) else {
            panic!("walls and boxes are meshes")
        };
        assert_eq!(m.indices, rm.indices);
        for (p, q) in m.positions.iter().zip(&rm.positions) {
            assert!(p.abs_diff_eq(*q, 1e-5), "{p} vs {q}");
        }
        assert_eq!(
            b.material_names()[s.material as usize],
            reference.material_names()[r.material as usize]
        );
    }
    let scene = b.build().unwrap();
    let reference = reference.build().unwrap();
    let (p, q) = (
        scene.total_power().to_rgb(),
        reference.total_power().to_rgb(),
    );
    for (a, e) in p.iter().zip(q) {
        assert!((a - e).abs() <= 1e-4 * e, "{p:?} vs {q:?}");
    }
    // Same power and bounds.
    assert!(scene.bounds().min.abs_diff_eq(reference.bounds().min, 1e-5));
    assert!(scene.bounds().max.abs_diff_eq(reference.bounds().max, 1e-5));
    // Defines override the defaults.
    let b = load_mitsuba(
        &file,
        &[("spp".into(), "4".into()), ("res".into(), "32".into())],
    )
    .unwrap();
    assert_eq!(b.settings.spp, Some(4));
    assert_eq!(b.camera().unwrap().width, 32);
}

#[test]
fn malformed_input_names_line_and_column() {
    // Unclosed tag.
    let text = "<scene version=\"3.0.0\">\n  <bsdf type=\"diffuse\">\n</scene>\n";
    match parse_mitsuba(text, &path(), &[]) {
        Err(LoadError::Parse {
            line,
            column,
            message,
            ..
        }) => {
            assert_eq!((line, column), (3, 1), "{message}"); // at the mismatched </scene>
            assert!(message.contains("malformed XML"), "{message}");
        }
        other => panic!("{:?}", other.err()),
    }
    // Bad numbers.
    for (v, col) in [("1.0.0", 50), ("nan", 50), ("1e999", 50), ("1e39", 50)] {
        expect_err(
            parse(&format!(
                r#"<shape type="sphere"><float name="radius" value="{v}"/></shape>"#
            )),
            2,
            Some(col),
            &[v],
        );
    }
    // Unknown attribute value.
    expect_err(
        parse(r#"<shape type="sphere"><boolean name="flip_normals" value="maybe"/></shape>"#),
        2,
        Some(58),
        &["maybe"],
    );
    expect_err(parse("<bsdf/>"), 2, Some(1), &["type"]);
    match parse_mitsuba("<scene version=\"0.6.0\"/>", &path(), &[]) {
        Err(LoadError::Parse { message, .. }) => assert!(message.contains("0.6.0")),
        other => panic!("{:?}", other.err()),
    }
}

#[test]
fn unsupported_elements_give_one_warning_with_lines() {
    let body = r#"<texture type="checkerboard" id="t"/>
<bsdf type="diffuse"><float name="sheen" value="1"/></bsdf>
<medium type="homogeneous"/>"#;
    let b = parse(body).unwrap();
    let w = b.pending_warnings();
    assert_eq!(w.len(), 1, "{w:?}");
    assert!(w[0].contains("3 unsupported"), "{w:?}");
    for needle in [
        "checkerboard",
        "scene.xml:2",
        "sheen",
        "scene.xml:3",
        "homogeneous",
        "scene.xml:4",
    ] {
        assert!(w[0].contains(needle), "'{needle}' missing: {w:?}");
    }
}

#[test]
fn includes_resolve_and_cycles_fail() {
    let dir = std::env::temp_dir().join(format!("caustica-mitsuba-inc-{}", std::process::id()));
    std::fs::create_dir_all(dir.join("sub")).unwrap();
    std::fs::write(
        dir.join("sub/mat.xml"),
        r#"<scene version="3.0.0"><bsdf type="diffuse" id="m"/></scene>"#,
    )
    .unwrap();
    std::fs::write(
        dir.join("main.xml"),
        format!("<scene version=\"3.0.0\">{CAM}<include filename=\"sub/mat.xml\"/><shape type=\"sphere\"><ref id=\"m\"/></shape></scene>"),
    )
    .unwrap();
    let b = load_mitsuba(&dir.join("main.xml"), &[]).unwrap();
    assert_eq!(b.material_names(), ["m"]);
    assert!(b.build().is_ok());
    // a → b → a.
    std::fs::write(
        dir.join("a.xml"),
        r#"<scene version="3.0.0"><include filename="b.xml"/></scene>"#,
    )
    .unwrap();
    std::fs::write(
        dir.join("b.xml"),
        "<scene version=\"3.0.0\">\n<include filename=\"a.xml\"/></scene>",
    )
    .unwrap();
    match load_mitsuba(&dir.join("a.xml"), &[]) {
        Err(LoadError::Parse {
            path,
            line,
            message,
            ..
        }) => {
            assert!(path.ends_with("b.xml"), "{path:?}");
            assert_eq!(line, 2);
            assert!(message.contains("cyclic"), "{message}");
        }
        other => panic!("{:?}", other.err()),
    }
    // A nested bsdf with an id can be referenced later.
    let b = parse(
        r#"<shape type="sphere"><bsdf type="diffuse" id="inner"/></shape>
<shape type="sphere"><ref id="inner"/></shape>"#,
    )
    .unwrap();
    assert_eq!(b.shapes()[0].material, b.shapes()[1].material);
    // A chain of 40 distinct includes exceeds the depth limit.
    for i in 0..40 {
        std::fs::write(
            dir.join(format!("chain{i}.xml")),
            format!(
                "<scene version=\"3.0.0\"><include filename=\"chain{}.xml\"/></scene>",
                i + 1
            ),
        )
        .unwrap();
    }
    std::fs::write(dir.join("chain40.xml"), "<scene version=\"3.0.0\"/>").unwrap();
    match load_mitsuba(&dir.join("chain0.xml"), &[]) {
        Err(LoadError::Parse { message, .. }) => assert!(message.contains("deeper"), "{message}"),
        other => panic!("{:?}", other.err()),
    }
    std::fs::write(dir.join("chain8.xml"), "<scene version=\"3.0.0\"/>").unwrap();
    assert!(load_mitsuba(&dir.join("chain0.xml"), &[]).is_ok());
    // Self-include.
    std::fs::write(
        dir.join("self.xml"),
        r#"<scene version="3.0.0"><include filename="self.xml"/></scene>"#,
    )
    .unwrap();
    assert!(matches!(
        load_mitsuba(&dir.join("self.xml"), &[]),
        Err(LoadError::Parse { .. })
    ));
}

#[test]
fn hostile_input_does_not_panic() {
    // Deeply nested elements and twosided BSDFs.
    let deep = format!(
        "<scene version=\"3.0.0\">{}{}</scene>",
        "<a>".repeat(20000),
        "</a>".repeat(20000)
    );
    let b = parse_mitsuba(&deep, &path(), &[]).unwrap();
    assert_eq!(b.pending_warnings().len(), 1);
    let nested = format!(
        "<bsdf type=\"twosided\" id=\"x\">{}<bsdf type=\"diffuse\"/>{}</bsdf>",
        "<bsdf type=\"twosided\">".repeat(100),
        "</bsdf>".repeat(100)
    );
    assert!(matches!(parse(&nested), Err(LoadError::Parse { .. })));
    // Huge and odd values.
    assert!(parse(r#"<shape type="sphere"><float name="radius" value="-1"/></shape>"#).is_err());
    assert!(
        parse(r#"<emitter type="point"><rgb name="intensity" value="1 2"/></emitter>"#).is_err()
    );
    assert!(parse(r#"<sensor type="perspective"><float name="fov" value="30"/><film type="hdrfilm"><integer name="width" value="99999999999"/></film></sensor>"#).is_err());
    assert!(parse(r#"<shape type="cube"><transform name="to_world"><rotate angle="3"/></transform></shape>"#).is_err());
    assert!(parse("").is_ok());
    assert!(parse_mitsuba("", &path(), &[]).is_err());
    assert!(parse_mitsuba("<notascene/>", &path(), &[]).is_err());
}

#[test]
fn bitmap_textures_nested_and_referenced() {
    let dir = std::env::temp_dir().join(format!("caustica-mitsuba-tex-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let mut img = caustica_core::image_io::Image::new(2, 1);
    img.set(0, 0, [0.25, 0.5, 0.75]);
    img.set(1, 0, [0.125, 0.125, 0.125]);
    img.write_pfm(&dir.join("t.pfm")).unwrap();
    let text = r#"<scene version="3.0.0">
<texture type="bitmap" id="tex"><string name="filename" value="t.pfm"/></texture>
<bsdf type="diffuse" id="a"><ref name="reflectance" id="tex"/></bsdf>
<bsdf type="diffuse" id="b"><texture type="bitmap" name="reflectance"><string name="filename" value="t.pfm"/></texture></bsdf>
</scene>"#;
    let b = parse_mitsuba(text, &dir.join("s.xml"), &[]).unwrap();
    for m in b.materials() {
        let Material::Diffuse { reflectance: t } = m else {
            panic!()
        };
        assert!(matches!(t, Texture::Image(_)));
        // Texel centre (0.25, 0.5) of the 2×1 image is the first pixel.
        let v = t.eval(caustica_core::Vec2::new(0.25, 0.5)).to_rgb();
        assert!(
            (v[0] - 0.25).abs() < 1e-6 && (v[2] - 0.75).abs() < 1e-6,
            "{v:?}"
        );
    }
    assert!(
        b.pending_warnings().is_empty(),
        "{:?}",
        b.pending_warnings()
    );
    let missing = r#"<scene version="3.0.0"><texture type="bitmap" id="t"><string name="filename" value="none.png"/></texture></scene>"#;
    assert!(matches!(
        parse_mitsuba(missing, &dir.join("s.xml"), &[]),
        Err(LoadError::File { .. })
    ));
}

/// Random edits of a valid scene (deleting, duplicating or replacing short spans with
/// XML-significant tokens) must give a scene or an error, never a panic.
#[test]
fn random_edits_never_panic() {
    let file = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/mitsuba/cornell-box.xml");
    let text = std::fs::read_to_string(&file).unwrap();
    let tokens = [
        "<",
        ">",
        "/>",
        "\"",
        "$spp",
        "-1",
        "1e999",
        "nan",
        "0",
        "<ref id=\"white\"/>",
        "<bsdf type=\"twosided\">",
        "</shape>",
        "<transform name=\"to_world\">",
        "&amp;",
        "&#0;",
        "<!--",
        "<include filename=\"cornell-box.xml\"/>",
        "inf",
        ",",
        " ",
    ];
    let mut rng = caustica_core::sampling::Pcg32::new(7, 3);
    let (mut ok, mut errors) = (0, 0);
    for _ in 0..1500 {
        let mut t = text.clone().into_bytes();
        for _ in 0..1 + rng.next_u32() % 3 {
            let at = rng.next_u32() as usize % t.len();
            let len = (rng.next_u32() as usize % 8).min(t.len() - at);
            match rng.next_u32() % 3 {
                0 => {
                    t.drain(at..at + len);
                }
                1 => {
                    let dup: Vec<u8> = t[at..at + len].to_vec();
                    t.splice(at..at, dup);
                }
                _ => {
                    let tok = tokens[rng.next_u32() as usize % tokens.len()];
                    t.splice(at..at + len, tok.bytes());
                }
            }
        }
        let Ok(s) = String::from_utf8(t) else {
            continue;
        };
        match parse_mitsuba(&s, &file, &[]) {
            Ok(_) => ok += 1,
            Err(_) => errors += 1,
        }
    }
    // Both outcomes occur (the edits are neither all harmless nor all fatal).
    assert!(ok > 0 && errors > 0, "{ok} ok, {errors} errors");
}

#[test]
fn default_bsdf_is_grey_but_black_for_area_emitters() {
    // Mitsuba: a shape without a BSDF gets diffuse 0.5, an area-emitter shape a black one (its
    // surface does not reflect). Measured against Mitsuba 3.9 (docs/mitsuba.md).
    let b = parse(&format!(
        r#"{CAM}
<shape type="rectangle"/>
<shape type="sphere"><emitter type="area"><rgb name="radiance" value="1"/></emitter></shape>
<shape type="disk"/>"#
    ))
    .unwrap();
    let albedo = |i: usize| match &b.materials()[b.shapes()[i].material as usize] {
        Material::Diffuse {
            reflectance: Texture::Constant(c),
        } => c.to_rgb(),
        m => panic!("{m:?}"),
    };
    assert_eq!(albedo(0), [0.5; 3]);
    assert_eq!(albedo(1), [0.0; 3]);
    assert_eq!(albedo(2), [0.5; 3]);
    assert_eq!(b.shapes()[0].material, b.shapes()[2].material);
}

#[test]
fn substitution_cannot_grow_exponentially() {
    // "Billion laughs": each parameter is ten copies of the previous one, so a0..a9 would
    // reach 10¹⁰ bytes. a4 (10⁵ bytes) is the first past the limit (line 6 = a4's line).
    let mut body = String::from("<default name=\"a0\" value=\"xxxxxxxxxx\"/>\n");
    for i in 1..10 {
        body += &format!(
            "<default name=\"a{i}\" value=\"{}\"/>\n",
            format!("$a{}", i - 1).repeat(10)
        );
    }
    expect_err(parse(&body), 6, Some(27), &["longer than", "$a3"]);
    // Long values are fine below the limit.
    let ok = format!(
        "<default name=\"a\" value=\"{}\"/><default name=\"b\" value=\"$a$a\"/>",
        "x".repeat(1000)
    );
    assert_eq!(parse(&ok).unwrap().pending_warnings().len(), 0);
}

#[cfg(unix)]
#[test]
fn devices_and_directories_are_not_read() {
    // Reading /dev/zero would never end; a directory is not a scene or mesh either.
    expect_err(
        parse(r#"<include filename="/dev/zero"/>"#),
        2,
        Some(20),
        &["/dev/zero", "not a regular file"],
    );
    expect_err(
        parse(r#"<shape type="obj"><string name="filename" value="/dev/zero"/></shape>"#),
        2,
        Some(50),
        &["not a regular file"],
    );
    let dir = std::env::temp_dir();
    let ply = format!(
        r#"<shape type="ply"><string name="filename" value="{}"/></shape>"#,
        dir.display()
    );
    expect_err(parse(&ply), 2, Some(50), &["not a regular file"]);
    let tex = format!(
        r#"<texture type="bitmap" id="t"><string name="filename" value="{}"/></texture>"#,
        dir.display()
    );
    expect_err(parse(&tex), 2, None, &["not a regular file"]);
    // A missing file is still a file error naming the path.
    match parse(r#"<include filename="missing.xml"/>"#) {
        Err(LoadError::File { path, .. }) => assert!(path.ends_with("missing.xml")),
        r => panic!("expected a file error, got {:?}", r.err()),
    }
}

#[test]
fn absurd_film_sizes_are_errors() {
    let film = |w: &str, h: &str| {
        format!(
            r#"<sensor type="perspective"><float name="fov" value="30"/><film type="hdrfilm"><integer name="width" value="{w}"/><integer name="height" value="{h}"/></film></sensor>"#
        )
    };
    expect_err(
        parse(&film("100000", "100000")),
        2,
        Some(108),
        &["width", "65536", "100000"],
    );
    // Each side is allowed, the product (2³² pixels, ~200 GB of film) is not.
    expect_err(
        parse(&film("65536", "65536")),
        2,
        Some(58),
        &["65536x65536", "too large"],
    );
    let b = parse(&film("16384", "16384")).unwrap();
    let cam = b.camera().unwrap();
    assert_eq!((cam.width, cam.height), (16384, 16384));
}

#[test]
fn huge_shapes_are_errors_not_bvh_panics() {
    // Found by the mitsuba_build fuzz target: a sphere 10¹⁹ m across gave the BVH builder
    // infinite surface areas and it tripped an assertion (or built a broken tree).
    let big = "<shape type=\"sphere\"><float name=\"radius\" value=\"1e19\"/></shape>\n<shape type=\"sphere\"/>";
    expect_err(parse(big), 2, Some(1), &["sphere", "beyond", "1e12"]);
    let scaled = |ty: &str| {
        format!(
            "<shape type=\"{ty}\"><transform name=\"to_world\"><scale value=\"1e13\"/></transform></shape>"
        )
    };
    expect_err(
        parse(&scaled("cube")),
        2,
        Some(1),
        &["mesh vertex", "beyond"],
    );
    let far_disk = r#"<shape type="disk"><transform name="to_world"><translate x="2e12"/></transform></shape>"#;
    expect_err(parse(far_disk), 2, Some(1), &["disk", "beyond"]);
    // Large but bounded scenes still build.
    let ok = format!(
        "<shape type=\"sphere\"><float name=\"radius\" value=\"1e11\"/></shape>\n<shape type=\"sphere\"/>{}\n{CAM}",
        scaled("rectangle").replace("1e13", "1e11")
    );
    assert!(parse(&ok).unwrap().build().is_ok());
}

// ---- participating media ----

use crate::vol::encode_vol;
use caustica_scene::intersection::NONE;
use caustica_scene::medium::{Medium, MediumKind};
use caustica_scene::phase::PhaseFunction;

/// A fresh temporary folder for `.vol` files.
fn media_dir(tag: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("caustica-media-{tag}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Parses `body` as if read from `dir/scene.xml`.
fn parse_at(dir: &Path, body: &str) -> Result<SceneBuilder, LoadError> {
    let text = format!("<scene version=\"3.0.0\">\n{body}\n</scene>\n");
    parse_mitsuba(&text, &dir.join("scene.xml"), &[])
}

fn close3(a: Spectrum, b: [f32; 3]) -> bool {
    (0..3).all(|i| (a.c[i] - b[i]).abs() <= 1e-6 * b[i].abs().max(1.0))
}

fn medium_of(b: &SceneBuilder, i: usize) -> &Medium {
    &b.media()[i]
}

#[test]
fn homogeneous_media_take_every_parameter_form() {
    let body = r#"<medium type="homogeneous" id="a">
  <rgb name="sigma_t" value="0.45, 0.55, 0.65"/>
  <rgb name="albedo" value="0.5, 0.2, 1"/>
  <float name="scale" value="2"/>
</medium>
<medium type="homogeneous" id="b">
  <float name="sigma_t" value="3"/>
  <volume type="constvolume" name="albedo"><rgb name="value" value="0.25, 0.5, 0.75"/></volume>
  <phase type="hg"><float name="g" value="0.6"/></phase>
</medium>
<medium type="homogeneous" id="c">
  <spectrum name="sigma_a" value="0.05"/>
  <rgb name="sigma_s" value="0.4 0.5 0.6"/>
  <float name="scale" value="10"/>
  <phase type="isotropic"/>
</medium>
<medium type="homogeneous" id="d"><phase type="hg"/></medium>
<medium type="homogeneous" id="e">
  <volume type="constvolume" name="sigma_t"><float name="value" value="2"/></volume>
  <float name="albedo" value="0.5"/>
</medium>"#;
    let b = parse(body).unwrap();
    assert!(
        b.pending_warnings().is_empty(),
        "{:?}",
        b.pending_warnings()
    );
    assert_eq!(b.media().len(), 5);
    // scale multiplies sigma_t: sigma_s = albedo * scale * sigma_t.
    let a = medium_of(&b, 0);
    assert!(matches!(a.kind, MediumKind::Homogeneous(_)));
    assert!(close3(a.sigma_s, [0.45, 0.22, 1.3]), "{:?}", a.sigma_s);
    assert!(close3(a.sigma_a, [0.45, 0.88, 0.0]), "{:?}", a.sigma_a);
    assert_eq!(a.phase, PhaseFunction::default());
    let m = medium_of(&b, 1);
    assert!(close3(m.sigma_s, [0.75, 1.5, 2.25]) && close3(m.sigma_a, [2.25, 1.5, 0.75]));
    assert_eq!(m.phase, PhaseFunction::henyey_greenstein(0.6).unwrap());
    let m = medium_of(&b, 2);
    assert!(close3(m.sigma_a, [0.5; 3]) && close3(m.sigma_s, [4.0, 5.0, 6.0]));
    assert_eq!(m.phase, PhaseFunction::default());
    // Mitsuba 3's defaults: sigma_t 1, albedo 0.75, hg g 0.8.
    let m = medium_of(&b, 3);
    assert!(close3(m.sigma_s, [0.75; 3]) && close3(m.sigma_a, [0.25; 3]));
    assert_eq!(m.phase, PhaseFunction::henyey_greenstein(0.8).unwrap());
    let m = medium_of(&b, 4);
    assert!(close3(m.sigma_s, [1.0; 3]) && close3(m.sigma_a, [1.0; 3]));
    assert_eq!(b.medium_index("c"), Some(2));
}

#[test]
fn shapes_sensor_and_emitters_refer_to_media() {
    let body = r#"<medium type="homogeneous" id="fog"><float name="sigma_t" value="0.5"/></medium>
<medium type="homogeneous" id="haze"><float name="sigma_t" value="0.1"/></medium>
<bsdf type="null" id="pass"/>
<shape type="cube"><ref id="pass"/><ref name="interior" id="fog"/></shape>
<shape type="sphere"><float name="radius" value="0.2"/><point name="center" x="3" y="0" z="0"/>
  <bsdf type="dielectric"/>
  <medium type="homogeneous" name="interior"><float name="sigma_t" value="2"/></medium>
  <ref name="exterior" id="fog"/>
</shape>
<shape type="sphere"><float name="radius" value="0.1"/><point name="center" x="-3" y="0" z="0"/></shape>
<emitter type="point"><point name="position" x="0" y="0.5" z="0"/></emitter>
<emitter type="spot"><ref id="fog"/><transform name="to_world"><lookat origin="5,5,5" target="0,0,0"/></transform></emitter>
<emitter type="point"><point name="position" x="9" y="0" z="0"/>
  <medium type="homogeneous"><float name="sigma_t" value="7"/></medium></emitter>
<sensor type="perspective"><float name="fov" value="40"/><ref id="haze"/>
<film type="hdrfilm"><integer name="width" value="8"/><integer name="height" value="8"/></film></sensor>"#;
    let b = parse(body).unwrap();
    assert!(
        b.pending_warnings().is_empty(),
        "{:?}",
        b.pending_warnings()
    );
    assert_eq!(b.media().len(), 4);
    assert!(b.materials()[b.shapes()[0].material as usize].is_null());
    let faces = |i: usize| (b.shapes()[i].medium_inside, b.shapes()[i].medium_outside);
    assert_eq!(faces(0), (0, NONE), "cube: interior fog");
    assert_eq!(faces(1), (2, 0), "sphere: inline interior, exterior fog");
    assert_eq!(faces(2), (NONE, NONE), "not a boundary");
    assert!(close3(b.media()[2].sigma_t(), [2.0; 3]));
    let scene = b.build().unwrap();
    // The camera at the origin is in the fog's cube, but its ref puts it in the haze.
    assert_eq!(scene.camera_medium, 1);
    // Point light inside the cube: found; spot light outside it but given; the last one given
    // inline.
    assert_eq!(scene.light_media, vec![0, 0, 3]);
    assert_eq!(scene.medium_at(Vec3::new(3.0, 0.0, 0.0)), 2);
    assert_eq!(scene.medium_at(Vec3::new(-5.0, 0.0, 0.0)), NONE);
}

#[test]
fn camera_medium_can_be_inline_and_differs_from_its_position() {
    let body = r#"<medium type="homogeneous" id="fog"><float name="sigma_t" value="0.5"/></medium>
<shape type="cube"><bsdf type="null"/><ref name="interior" id="fog"/>
  <transform name="to_world"><translate x="10"/></transform></shape>
<sensor type="perspective"><float name="fov" value="40"/>
  <medium type="homogeneous" id="air"><float name="sigma_t" value="0.01"/></medium>
<film type="hdrfilm"><integer name="width" value="8"/><integer name="height" value="8"/></film></sensor>"#;
    let scene = parse(body).unwrap().build().unwrap();
    assert_eq!(scene.camera_medium, 1);
    assert_eq!(
        scene.medium_names,
        vec!["fog".to_string(), "air".to_string()]
    );
    assert_eq!(scene.light_media, Vec::<u32>::new());
    // Without the nested medium the camera (at the origin, outside the cube) is in vacuum.
    let body = body.replace(
        r#"<medium type="homogeneous" id="air"><float name="sigma_t" value="0.01"/></medium>"#,
        "",
    );
    assert_eq!(parse(&body).unwrap().build().unwrap().camera_medium, NONE);
}

#[test]
fn heterogeneous_media_read_vol_grids_placed_by_to_world() {
    let dir = media_dir("grid");
    let data: Vec<f32> = (0..24).map(|i| i as f32 / 8.0).collect();
    let bbox = [Vec3::new(10.0, 10.0, 10.0), Vec3::new(12.0, 11.0, 14.0)];
    std::fs::create_dir_all(dir.join("vols")).unwrap();
    std::fs::write(
        dir.join("vols/d.vol"),
        encode_vol([4, 3, 2], 1, bbox, &data),
    )
    .unwrap();
    let body = r#"<medium type="heterogeneous" id="smoke">
  <volume type="gridvolume" name="sigma_t"><string name="filename" value="vols/d.vol"/>
    <transform name="to_world"><scale x="2" y="3" z="4"/><translate x="-1" y="0" z="1"/></transform>
  </volume>
  <rgb name="albedo" value="0.9 0.8 0.7"/>
  <float name="scale" value="6"/>
</medium>
<medium type="heterogeneous" id="plain">
  <volume type="gridvolume" name="sigma_t"><string name="filename" value="vols/d.vol"/></volume>
  <volume type="constvolume" name="albedo"><float name="value" value="0.5"/></volume>
</medium>
<medium type="heterogeneous" id="boxed">
  <volume type="gridvolume" name="sigma_t"><string name="filename" value="vols/d.vol"/>
    <boolean name="use_grid_bbox" value="true"/></volume>
</medium>
<medium type="heterogeneous" id="const">
  <volume type="constvolume" name="sigma_t"><rgb name="value" value="1 2 3"/></volume>
  <float name="albedo" value="0.5"/><float name="scale" value="2"/>
</medium>"#;
    let b = parse_at(&dir, body).unwrap();
    assert!(
        b.pending_warnings().is_empty(),
        "{:?}",
        b.pending_warnings()
    );
    let m = medium_of(&b, 0);
    let MediumKind::Grid(g) = &m.kind else {
        panic!("a grid")
    };
    assert_eq!(g.resolution(), [4, 3, 2]);
    // sigma_t at density 1 is the scale; albedo splits it.
    assert!(close3(m.sigma_t(), [6.0; 3]) && close3(m.sigma_s, [5.4, 4.8, 4.2]));
    // Voxel (i, j, k) sits at to_world((i + 1/2)/4, (j + 1/2)/3, (k + 1/2)/2); the file's box
    // is not used.
    let voxel = |g: &caustica_scene::medium::DensityGrid, t: &dyn Fn(Vec3) -> Vec3| {
        for k in 0..2 {
            for j in 0..3 {
                for i in 0..4 {
                    let u = Vec3::new(
                        (i as f32 + 0.5) / 4.0,
                        (j as f32 + 0.5) / 3.0,
                        (k as f32 + 0.5) / 2.0,
                    );
                    let want = data[(k * 3 + j) * 4 + i];
                    let got = g.density(t(u));
                    assert!(
                        (got - want).abs() < 1e-5,
                        "voxel {i} {j} {k}: {got} vs {want}"
                    );
                }
            }
        }
    };
    voxel(g, &|u| {
        u * Vec3::new(2.0, 3.0, 4.0) + Vec3::new(-1.0, 0.0, 1.0)
    });
    assert_eq!(g.density(Vec3::new(11.0, 10.5, 12.0)), 0.0);
    let MediumKind::Grid(g) = &medium_of(&b, 1).kind else {
        panic!()
    };
    voxel(g, &|u| u);
    assert!(close3(medium_of(&b, 1).sigma_s, [0.5; 3]));
    let MediumKind::Grid(g) = &medium_of(&b, 2).kind else {
        panic!()
    };
    voxel(g, &|u| bbox[0] + (bbox[1] - bbox[0]) * u);
    // A constant sigma_t: a homogeneous medium.
    let m = medium_of(&b, 3);
    assert!(matches!(m.kind, MediumKind::Homogeneous(_)));
    assert!(close3(m.sigma_t(), [2.0, 4.0, 6.0]) && close3(m.sigma_s, [1.0, 2.0, 3.0]));
    // Three channels are averaged, with an approximation warning naming the file.
    std::fs::write(
        dir.join("rgb.vol"),
        encode_vol([1, 1, 1], 3, bbox, &[1.0, 2.0, 6.0]),
    )
    .unwrap();
    let b = parse_at(
        &dir,
        r#"<medium type="heterogeneous" id="m"><volume type="gridvolume" name="sigma_t">
<string name="filename" value="rgb.vol"/></volume></medium>"#,
    )
    .unwrap();
    let MediumKind::Grid(g) = &medium_of(&b, 0).kind else {
        panic!()
    };
    assert_eq!(g.max_density(), 3.0);
    let w = b.pending_warnings();
    assert!(
        w.len() == 1 && w[0].contains("rgb.vol") && w[0].contains("averaged"),
        "{w:?}"
    );
    std::fs::remove_dir_all(&dir).ok();
}

/// Expects a parse error in `dir/scene.xml` at `line` naming every word of `words`.
#[track_caller]
fn expect_media_err(dir: &Path, body: &str, line: usize, words: &[&str]) {
    let r = parse_at(dir, body);
    if let Err(LoadError::Parse { path, .. }) = &r {
        assert_eq!(path, &dir.join("scene.xml"));
    }
    expect_err(r, line, None, words);
}

#[test]
fn bad_media_are_errors_naming_file_line_and_expectation() {
    let dir = media_dir("bad");
    let bbox = [Vec3::ZERO, Vec3::ONE];
    let good = encode_vol([2, 2, 2], 1, bbox, &[1.0; 8]);
    std::fs::write(dir.join("short.vol"), &good[..good.len() - 4]).unwrap();
    std::fs::write(dir.join("magic.vol"), b"VOX\x03rest-of-it").unwrap();
    std::fs::write(dir.join("empty.vol"), encode_vol([2, 0, 2], 1, bbox, &[])).unwrap();
    let mut nan = vec![1.0; 8];
    nan[5] = f32::NAN;
    std::fs::write(dir.join("nan.vol"), encode_vol([2, 2, 2], 1, bbox, &nan)).unwrap();
    let mut neg = vec![1.0; 8];
    neg[2] = -0.5;
    std::fs::write(dir.join("neg.vol"), encode_vol([2, 2, 2], 1, bbox, &neg)).unwrap();
    let grid = |file: &str| {
        format!(
            "<medium type=\"heterogeneous\" id=\"m\">\n<volume type=\"gridvolume\" name=\"sigma_t\">\n<string name=\"filename\" value=\"{file}\"/></volume></medium>"
        )
    };
    let missing = dir.join("none.vol").display().to_string();
    expect_media_err(
        &dir,
        &grid("none.vol"),
        4,
        &["cannot read grid file", &missing],
    );
    expect_media_err(
        &dir,
        &grid("short.vol"),
        4,
        &["short.vol", "truncated", "needs 80 bytes", "has 76"],
    );
    expect_media_err(&dir, &grid("magic.vol"), 4, &["magic.vol", "'VOL'"]);
    expect_media_err(
        &dir,
        &grid("empty.vol"),
        4,
        &["empty.vol", "zero-size", "2×0×2"],
    );
    expect_media_err(
        &dir,
        &grid("nan.vol"),
        4,
        &["nan.vol", "voxel (x 1, y 0, z 1)", "NaN"],
    );
    expect_media_err(
        &dir,
        &grid("neg.vol"),
        4,
        &["neg.vol", "non-negative", "-0.5"],
    );
    // Coefficients.
    let homo = |inner: &str| format!("<medium type=\"homogeneous\" id=\"m\">\n{inner}</medium>");
    expect_media_err(
        &dir,
        &homo(r#"<rgb name="sigma_t" value="1, -2, 1"/>"#),
        3,
        &["sigma_t", "non-negative", "-2"],
    );
    expect_media_err(
        &dir,
        &homo("<float name=\"sigma_a\" value=\"1\"/>\n<float name=\"sigma_s\" value=\"-1\"/>"),
        4,
        &["sigma_s", "non-negative"],
    );
    expect_media_err(
        &dir,
        &homo(r#"<float name="sigma_t" value="nan"/>"#),
        3,
        &["finite", "nan"],
    );
    expect_media_err(
        &dir,
        &homo(r#"<float name="albedo" value="1.5"/>"#),
        3,
        &["albedo", "[0, 1]"],
    );
    expect_media_err(
        &dir,
        &homo(r#"<float name="scale" value="-1"/>"#),
        3,
        &["scale", "non-negative"],
    );
    expect_media_err(
        &dir,
        &homo(r#"<float name="sigma_a" value="1"/>"#),
        2,
        &["sigma_a", "sigma_s"],
    );
    expect_media_err(
        &dir,
        &homo(
            r#"<float name="sigma_t" value="1"/><float name="sigma_a" value="1"/><float name="sigma_s" value="1"/>"#,
        ),
        2,
        &["not both"],
    );
    // Phase functions.
    for g in ["1", "-1", "1.5"] {
        expect_media_err(
            &dir,
            &homo(&format!(
                "<phase type=\"hg\"><float name=\"g\" value=\"{g}\"/></phase>"
            )),
            3,
            &["hg", "(-1, 1)", g],
        );
    }
    expect_media_err(
        &dir,
        &homo(r#"<phase type="rayleigh"/>"#),
        3,
        &["rayleigh", "isotropic, hg"],
    );
    expect_media_err(
        &dir,
        r#"<medium type="fancy" id="m"/>"#,
        2,
        &["fancy", "homogeneous, heterogeneous"],
    );
    // References.
    expect_media_err(
        &dir,
        "<shape type=\"cube\">\n<ref name=\"interior\" id=\"fog\"/></shape>",
        3,
        &["medium 'fog'", "not defined"],
    );
    expect_media_err(
        &dir,
        "<bsdf type=\"diffuse\" id=\"fog\"/>\n<shape type=\"cube\"><ref name=\"exterior\" id=\"fog\"/></shape>",
        3,
        &["'fog' is not a medium"],
    );
    expect_media_err(
        &dir,
        "<sensor type=\"perspective\"><float name=\"fov\" value=\"40\"/>\n<ref id=\"nowhere\"/></sensor>",
        3,
        &["medium 'nowhere'", "not defined"],
    );
    expect_media_err(
        &dir,
        "<shape type=\"cube\">\n<medium type=\"homogeneous\"/></shape>",
        3,
        &["interior", "exterior"],
    );
    // A grid albedo is refused (only sigma_t may vary).
    expect_media_err(
        &dir,
        &homo(
            "<volume type=\"gridvolume\" name=\"albedo\"><string name=\"filename\" value=\"x.vol\"/></volume>",
        ),
        3,
        &["albedo", "gridvolume"],
    );
    // Tracking that would not end is refused by the scene's check, at the medium's line.
    std::fs::write(dir.join("ones.vol"), &good).unwrap();
    expect_media_err(
        &dir,
        "<medium type=\"heterogeneous\" id=\"m\"><float name=\"scale\" value=\"1e30\"/>\n<volume type=\"gridvolume\" name=\"sigma_t\"><string name=\"filename\" value=\"ones.vol\"/></volume></medium>",
        2,
        &["medium 'm'", "optical depth"],
    );
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn open_medium_boundaries_are_warned_about() {
    let body = r#"<medium type="homogeneous" id="fog"/>
<shape type="rectangle" id="sheet"><ref name="interior" id="fog"/></shape>
<shape type="cube"><ref name="interior" id="fog"/></shape>
<shape type="sphere"><ref name="exterior" id="fog"/></shape>
<shape type="disk"><ref name="exterior" id="fog"/></shape>
<shape type="rectangle"/>"#;
    let b = parse(body).unwrap();
    let w = b.pending_warnings();
    assert_eq!(w.len(), 2, "{w:?}");
    assert!(
        w[0].contains("shape 'sheet'")
            && w[0].contains("scene.xml:3")
            && w[0].contains("not closed"),
        "{w:?}"
    );
    assert!(
        w[1].contains("disk") && w[1].contains("scene.xml:6"),
        "{w:?}"
    );
    // A closed mesh from a file is not warned about, an open one is.
    let dir = media_dir("closed");
    let tet = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";
    std::fs::write(dir.join("tet.obj"), tet).unwrap();
    std::fs::write(dir.join("open.obj"), &tet[..tet.len() - 8]).unwrap();
    for (file, warned) in [("tet.obj", false), ("open.obj", true)] {
        let b = parse_at(
            &dir,
            &format!(
                r#"<medium type="homogeneous" id="fog"/>
<shape type="obj"><string name="filename" value="{file}"/><ref name="interior" id="fog"/></shape>"#
            ),
        )
        .unwrap();
        let w = b.pending_warnings();
        assert_eq!(!w.is_empty(), warned, "{file}: {w:?}");
        if warned {
            assert!(w[0].contains("3 of its 6 edges"), "{w:?}");
        }
    }
    std::fs::remove_dir_all(&dir).ok();
}

/// Mitsuba's scalar_spectral reads `<spectrum value="x">` on an emitter as a flat spectrum
/// (illuminant E) and `<rgb>` as an upsampled illuminant: caustica's spectral mode does the same,
/// for point-like and area emitters alike (RGB mode sees grey x either way).
#[test]
fn spectrum_valued_emitters_are_flat_in_spectral_mode() {
    let body = r#"<sensor type="perspective"><float name="fov" value="40"/><film type="hdrfilm"><integer name="width" value="8"/><integer name="height" value="8"/></film></sensor>
<emitter type="point"><spectrum name="intensity" value="2"/></emitter>
<emitter type="point"><rgb name="intensity" value="2 2 2"/></emitter>
<shape type="rectangle"><emitter type="area"><spectrum name="radiance" value="3"/></emitter></shape>
<shape type="rectangle"><emitter type="area"><rgb name="radiance" value="3 3 3"/></emitter></shape>"#;
    let scene = parse(body).unwrap().build().unwrap();
    let kinds: Vec<bool> = scene
        .light_spectra
        .iter()
        .map(|e| matches!(e, caustica_scene::light::EmissionSpectrum::Flat))
        .collect();
    // Two flat (one point, one area), two upsampled; the order of lights is the loader's.
    assert_eq!(kinds.iter().filter(|&&f| f).count(), 2, "{kinds:?}");
    assert_eq!(scene.lights.len(), 4);
    for (l, flat) in scene.lights.iter().zip(&kinds) {
        let grey = match l {
            Light::Point(p) => p.intensity,
            Light::Area(a) => a.radiance,
            other => panic!("{other:?}"),
        };
        // Both conventions are grey in RGB mode.
        assert_eq!(grey.c[0], grey.c[2], "{flat}");
    }
}
