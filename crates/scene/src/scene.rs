//! The assembled scene and its builder.

use crate::camera::PerspectiveCamera;
use crate::error::SceneError;
use crate::geometry::Geometry;
use crate::intersection::NONE;
use crate::intersection::SurfaceInteraction;
use crate::light::{AreaLight, AreaShape, EmissionSpectrum, Light, ProjectionMap};
use crate::material::Material;
use crate::medium::{Medium, MediumInterface};
use crate::shape::{Aabb, Shape, ShapeGeometry};
use caustica_core::sampling::Distribution1D;
use caustica_core::{Channels, Ray, Spectrum};

/// Largest coordinate (m) a shape may reach. Beyond it the BVH builder's surface-area costs
/// overflow `f32` (a box 10¹⁹ wide already has an infinite area) and it builds a broken tree;
/// ±10¹² keeps area × primitive count finite for any mesh.
pub const MAX_COORDINATE: f32 = 1e12;

/// Pixel reconstruction filter requested by the scene.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub enum FilterKind {
    /// Box of one pixel.
    #[default]
    Box,
    /// Gaussian with standard deviation `stddev` (pixels), truncated at `radius` (pixels).
    Gaussian { stddev: f32, radius: f32 },
}

/// Render settings a scene file may suggest; the command line overrides them.
#[derive(Clone, Debug, Default)]
pub struct SceneSettings {
    pub spp: Option<u32>,
    pub filter: FilterKind,
    pub max_depth: Option<u32>,
    /// Integrator the scene file asks for (e.g. Mitsuba's `path` or `ptracer`), if any.
    pub integrator: Option<String>,
    /// Caustic photons the scene suggests for its photon integrator.
    pub photons: Option<u32>,
    /// Smoothing of photon differentials the scene suggests (pdm, pds; positive).
    pub smoothing: Option<f32>,
    /// Smoothing of volume photon differentials the scene suggests (vpd; positive).
    pub volume_smoothing: Option<f32>,
    /// Volume photons the scene suggests for its photon integrator.
    pub volume_photons: Option<u32>,
    /// Final-gather rays per camera sample the scene suggests (pm, dpm, pdm, pds; 0 = the
    /// global map seen directly).
    pub final_gather: Option<u32>,
    /// Frames per second of the scene's animation (scene files' `[animation] fps`; the
    /// built-in animated scenes: 25), if it has one: converts frames to seconds.
    pub fps: Option<f32>,
}

/// An immutable, ready-to-render scene.
pub struct Scene {
    pub name: String,
    pub geometry: Geometry,
    pub materials: Vec<Material>,
    pub material_names: Vec<String>,
    pub lights: Vec<Light>,
    pub camera: PerspectiveCamera,
    pub settings: SceneSettings,
    /// Light selection proportional to power (photon emission and next-event estimation).
    pub light_distribution: Option<Distribution1D>,
    /// Indices of infinite lights (seen by rays escaping the scene).
    pub infinite_lights: Vec<u32>,
    /// Non-fatal problems found while building (skipped triangles, approximated materials).
    pub warnings: Vec<String>,
    /// Participating media (indexed by the shapes' interfaces, `camera_medium`,
    /// `light_media`).
    pub media: Vec<Medium>,
    pub medium_names: Vec<String>,
    /// Medium the camera sits in, or [`NONE`] (vacuum).
    pub camera_medium: u32,
    /// Medium each light emits into (parallel to `lights`), or [`NONE`].
    pub light_media: Vec<u32>,
    /// True if some material is [`Material::Null`] or some medium exists: walkers must then
    /// follow rays through index-matched boundaries and media (otherwise they take the fast
    /// path of plain closest-hit and shadow rays).
    pub has_media: bool,
    /// The camera's shutter (frames); only moving meshes depend on it.
    pub shutter: Shutter,
    /// Spectral mode: paths sample wavelengths and the scene's RGB values are upsampled to
    /// spectra (`Channels`); false (RGB mode) by default. Set with [`Scene::set_spectral`].
    pub spectral: bool,
    /// How each light's RGB values become spectra (parallel to `lights`).
    pub light_spectra: Vec<EmissionSpectrum>,
    /// The lights' projection maps, built on first use ([`Scene::projection_map`]).
    projection: std::sync::OnceLock<ProjectionMap>,
}

impl Scene {
    /// Switches spectral mode on or off. Reflectance texels outside [0, 1] (image textures may
    /// hold any value), which the upsampling clamps, are counted in a warning added to
    /// `warnings`. Participating media need nothing here: their coefficients are upsampled
    /// where a path first meets them (`Medium::coefficients`, by the medium's `SpectralForm`).
    pub fn set_spectral(&mut self, on: bool) -> Result<(), SceneError> {
        self.spectral = on;
        if on {
            let outside: usize = self
                .materials
                .iter()
                .map(Material::reflectance_values_outside_unit_range)
                .sum();
            if outside > 0 {
                self.warnings.push(format!(
                    "{outside} reflectance texel value(s) outside [0, 1] clamped for spectral \
                     upsampling (Jakob–Hanika spectra are reflectances in [0, 1])"
                ));
            }
            for (e, l) in self.light_spectra.iter_mut().zip(&self.lights) {
                *e = e.prepared(l.power());
            }
        }
        Ok(())
    }

    /// The lanes a new path carries: RGB, or in spectral mode three wavelengths drawn from
    /// `u` (called only then, so RGB renders draw no extra number).
    #[inline]
    pub fn sample_channels(&self, u: impl FnOnce() -> f32) -> Channels {
        Channels::sample(self.spectral, u)
    }

    /// A value `rgb` light `li` returned (proportional to its colour) in the lanes `ch`.
    #[inline]
    pub fn light_emission(&self, li: usize, rgb: Spectrum, ch: &Channels) -> Spectrum {
        match ch {
            Channels::Rgb => rgb,
            _ => self.light_spectra[li].convert(rgb, ch),
        }
    }

    /// True if some mesh moves while the shutter is open (then rays carry a time).
    #[inline]
    pub fn has_motion(&self) -> bool {
        self.geometry.has_motion()
    }

    /// The time of a camera ray or light path for the uniform number `u`: uniform over the
    /// shutter in a moving scene, the shutter's opening otherwise (no random number is needed,
    /// so static renders do not change).
    #[inline]
    pub fn sample_time(&self, u: impl FnOnce() -> f32) -> f32 {
        if self.has_motion() && self.shutter.length > 0.0 {
            self.shutter.time(u())
        } else {
            self.shutter.open
        }
    }

    /// Closest hit along `ray`.
    #[inline]
    pub fn intersect(&self, ray: &Ray) -> Option<SurfaceInteraction> {
        self.geometry.intersect(ray)
    }
    /// True if `ray` is blocked before `ray.t_max`.
    #[inline]
    pub fn occluded(&self, ray: &Ray) -> bool {
        self.geometry.occluded(ray)
    }
    pub fn bounds(&self) -> Aabb {
        self.geometry.bounds()
    }
    /// Total emitted power of all lights (W).
    pub fn total_power(&self) -> Spectrum {
        self.lights.iter().map(|l| l.power()).sum()
    }
    /// Probability that light `i` is chosen by `light_distribution`.
    pub fn light_pmf(&self, i: u32) -> f32 {
        self.light_distribution
            .as_ref()
            .map_or(0.0, |d| d.pmf(i as usize))
    }

    /// The projection maps of the lights (which emission cells reach mirrors, glass or smooth
    /// metal), built from the BVH on the first call and kept: guided caustic emission.
    pub fn projection_map(&self) -> &ProjectionMap {
        self.projection.get_or_init(|| ProjectionMap::build(self))
    }

    /// The medium containing the point `p`, or [`NONE`] (vacuum): a ray from `p` in a fixed
    /// direction finds the first medium boundary and takes the medium on its near side.
    /// Shapes that are not boundaries are passed through. Assumes closed boundaries.
    pub fn medium_at(&self, p: caustica_core::Vec3) -> u32 {
        medium_at(&self.geometry, p)
    }
}

/// [`Scene::medium_at`] over the geometry alone (also used while building).
fn medium_at(geometry: &Geometry, p: caustica_core::Vec3) -> u32 {
    // An irrational direction, unlikely to graze edges of axis-aligned boxes.
    let d = caustica_core::Vec3::new(0.285_619_4, 0.518_421_7, 0.806_027_3).normalize();
    let mut ray = Ray::new(p, d);
    for _ in 0..4096 {
        let Some(si) = geometry.intersect(&ray) else {
            return NONE;
        };
        if si.is_medium_transition() {
            // Leaving through the +ng side means p is on the inside.
            return if d.dot(si.ng) > 0.0 {
                si.medium_inside
            } else {
                si.medium_outside
            };
        }
        ray = si.spawn_ray(d);
    }
    NONE
}

/// Collects materials, shapes, lights and the camera, validates them and builds a [`Scene`].
#[derive(Default)]
pub struct SceneBuilder {
    pub name: String,
    materials: Vec<Material>,
    material_names: Vec<String>,
    shapes: Vec<Shape>,
    lights: Vec<Light>,
    camera: Option<PerspectiveCamera>,
    pub settings: SceneSettings,
    pub warnings: Vec<String>,
    skipped_triangles: usize,
    media: Vec<Medium>,
    medium_names: Vec<String>,
    camera_medium: Option<u32>,
    /// Explicit media of lights (light index, medium).
    light_media: Vec<(usize, u32)>,
    /// Named emission spectra of lights (light index, spectrum); the others are RGB.
    light_spectra: Vec<(usize, EmissionSpectrum)>,
    shutter: Shutter,
}

/// When the camera's shutter is open, in frames of the scene's animation: from `open` for
/// `length` frames (seed 003's exposure `e`; the shutter time in seconds is `length / fps`).
/// Camera rays and light paths sample their time in `[open, open + length]`; a static scene
/// ignores it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Shutter {
    /// Time (frames) the shutter opens.
    pub open: f32,
    /// How long it stays open (frames, ≥ 0; 0: an instant).
    pub length: f32,
}

impl Default for Shutter {
    fn default() -> Self {
        Self {
            open: 0.0,
            length: 0.0,
        }
    }
}

impl Shutter {
    /// The shutter from frame `open` for `length ≥ 0` frames (both finite).
    pub fn new(open: f32, length: f32) -> Result<Self, SceneError> {
        if !(open.is_finite() && length.is_finite() && length >= 0.0) {
            return Err(SceneError::InvalidParameter(format!(
                "the shutter must open at a finite frame and stay open for a finite \
                 non-negative number of frames, got open {open}, length {length}"
            )));
        }
        Ok(Self { open, length })
    }

    /// The time `open + u · length` (frames) for `u ∈ [0, 1)`.
    #[inline]
    pub fn time(&self, u: f32) -> f32 {
        self.open + u * self.length
    }

    /// Time the shutter closes (frames).
    pub fn close(&self) -> f32 {
        self.open + self.length
    }
}

impl SceneBuilder {
    pub fn new(name: impl Into<String>) -> Self {
        Self {
            name: name.into(),
            ..Default::default()
        }
    }

    /// Adds a named material after checking its parameters; returns its index.
    pub fn add_material(&mut self, name: &str, m: Material) -> Result<u32, SceneError> {
        m.validate()
            .map_err(|e| SceneError::InvalidParameter(format!("material '{name}': {e}")))?;
        self.materials.push(m);
        self.material_names.push(name.to_string());
        Ok((self.materials.len() - 1) as u32)
    }

    /// Index of the material called `name`.
    pub fn material_index(&self, name: &str) -> Option<u32> {
        self.material_names
            .iter()
            .rposition(|n| n == name)
            .map(|i| i as u32)
    }

    /// Adds a named medium after checking it; returns its index.
    pub fn add_medium(&mut self, name: &str, m: Medium) -> Result<u32, SceneError> {
        m.validate()
            .map_err(|e| SceneError::InvalidParameter(format!("medium '{name}': {e}")))?;
        self.media.push(m);
        self.medium_names.push(name.to_string());
        Ok((self.media.len() - 1) as u32)
    }
    /// Index of the medium called `name`.
    pub fn medium_index(&self, name: &str) -> Option<u32> {
        self.medium_names
            .iter()
            .rposition(|n| n == name)
            .map(|i| i as u32)
    }
    /// Media added so far.
    pub fn media(&self) -> &[Medium] {
        &self.media
    }
    /// Puts the camera in medium `m` (otherwise the medium at the camera's position is found
    /// when the scene is built).
    pub fn set_camera_medium(&mut self, m: u32) {
        self.camera_medium = Some(m);
    }
    /// Says that light `light` (index into [`SceneBuilder::lights`]) emits into medium `m`
    /// (otherwise it is found from the light's position when the scene is built).
    pub fn set_light_medium(&mut self, light: usize, m: u32) {
        self.light_media.push((light, m));
    }

    /// [`SceneBuilder::add_shape`] with the media on the shape's two sides.
    pub fn add_shape_with_media(
        &mut self,
        geometry: ShapeGeometry,
        material: u32,
        emission: Option<Spectrum>,
        flip_normals: bool,
        media: MediumInterface,
    ) -> Result<(), SceneError> {
        for m in [media.inside, media.outside] {
            if m != NONE && m as usize >= self.media.len() {
                return Err(SceneError::Invalid(format!(
                    "medium index {m} does not exist"
                )));
            }
        }
        let before = self.shapes.len();
        self.add_shape(geometry, material, emission, flip_normals)?;
        if let Some(s) = self.shapes.get_mut(before) {
            s.medium_inside = media.inside;
            s.medium_outside = media.outside;
        }
        Ok(())
    }

    /// Adds a shape with material `material`; with `emission` (radiance, W/m²/sr) it also
    /// becomes a one-sided diffuse area light. Meshes are sanitised: non-finite and degenerate
    /// triangles are dropped and counted in a warning. Shapes reaching beyond
    /// ±[`MAX_COORDINATE`] are errors.
    pub fn add_shape(
        &mut self,
        mut geometry: ShapeGeometry,
        material: u32,
        emission: Option<Spectrum>,
        flip_normals: bool,
    ) -> Result<(), SceneError> {
        if material as usize >= self.materials.len() {
            return Err(SceneError::Invalid(format!(
                "material index {material} does not exist"
            )));
        }
        let mut flip_flag = false;
        match &mut geometry {
            ShapeGeometry::Mesh(m) => {
                let r = m.sanitize();
                self.skipped_triangles += r.total();
                if m.indices.is_empty() {
                    self.warnings
                        .push("a mesh has no valid triangles and was skipped".into());
                    return Ok(());
                }
                if let Some(v) = m
                    .indices
                    .iter()
                    .flatten()
                    .map(|&k| m.positions[k as usize])
                    .find(|v| v.abs().max_element() > MAX_COORDINATE)
                {
                    return Err(SceneError::InvalidParameter(format!(
                        "mesh vertex {v} lies beyond ±{MAX_COORDINATE:e}"
                    )));
                }
                if flip_normals {
                    for t in &mut m.indices {
                        t.swap(1, 2);
                    }
                    if let Some(ns) = &mut m.normals {
                        ns.iter_mut().for_each(|n| *n = -*n);
                    }
                }
            }
            ShapeGeometry::Sphere(s) => {
                if !(s.radius > 0.0 && s.radius.is_finite() && s.center.is_finite()) {
                    return Err(SceneError::InvalidParameter(format!(
                        "sphere radius must be positive and finite, got {}",
                        s.radius
                    )));
                }
                if s.center.abs().max_element() + s.radius > MAX_COORDINATE {
                    return Err(SceneError::InvalidParameter(format!(
                        "sphere (center {}, radius {}) reaches beyond ±{MAX_COORDINATE:e}",
                        s.center, s.radius
                    )));
                }
                flip_flag = flip_normals;
            }
            ShapeGeometry::Disk(d) => {
                if !(d.radius > 0.0
                    && d.radius.is_finite()
                    && d.center.is_finite()
                    && d.normal.length_squared() > 0.0)
                {
                    return Err(SceneError::InvalidParameter(format!(
                        "disk radius must be positive and finite, got {}",
                        d.radius
                    )));
                }
                if d.center.abs().max_element() + d.radius > MAX_COORDINATE {
                    return Err(SceneError::InvalidParameter(format!(
                        "disk (center {}, radius {}) reaches beyond ±{MAX_COORDINATE:e}",
                        d.center, d.radius
                    )));
                }
                d.normal = d.normal.normalize();
                if flip_normals {
                    d.normal = -d.normal;
                }
            }
        }
        let mut shape = Shape::new(geometry, material);
        shape.flip_normals = flip_flag;
        if let Some(le) = emission
            && !le.is_black()
        {
            if !le.is_finite() || le.min_component() < 0.0 {
                return Err(SceneError::InvalidParameter(format!(
                    "emitted radiance must be finite and non-negative, got {:?}",
                    le.c
                )));
            }
            if flip_flag {
                return Err(SceneError::Invalid(
                    "an emitting sphere cannot have flipped normals".into(),
                ));
            }
            let area_shape = match &shape.geometry {
                ShapeGeometry::Mesh(m) => AreaShape::Triangles(
                    m.indices
                        .iter()
                        .map(|t| t.map(|k| m.positions[k as usize]))
                        .collect(),
                ),
                ShapeGeometry::Sphere(s) => AreaShape::Sphere(*s),
                ShapeGeometry::Disk(d) => AreaShape::Disk(*d),
            };
            shape.light = self.lights.len() as u32;
            self.lights
                .push(Light::Area(AreaLight::new(area_shape, le, false)));
        }
        self.shapes.push(shape);
        Ok(())
    }

    /// Adds a mesh that moves with `motion` (its keyframes' vertex count must be the mesh's;
    /// the mesh's own positions are ignored in favour of the first keyframe's). Moving meshes
    /// cannot emit. A vertex that moves farther in one frame than 10× the diagonal of the
    /// mesh's first-frame bounds is refused as degenerate motion (the error names the frame).
    pub fn add_moving_mesh(
        &mut self,
        mesh: crate::shape::TriangleMesh,
        motion: crate::shape::MeshMotion,
        material: u32,
        flip_normals: bool,
    ) -> Result<(), SceneError> {
        self.add_moving_mesh_with_media(
            mesh,
            motion,
            material,
            flip_normals,
            MediumInterface::default(),
        )
    }

    /// [`Self::add_moving_mesh`] with the media on the mesh's two sides (as
    /// [`Self::add_shape_with_media`]).
    pub fn add_moving_mesh_with_media(
        &mut self,
        mut mesh: crate::shape::TriangleMesh,
        mut motion: crate::shape::MeshMotion,
        material: u32,
        flip_normals: bool,
        media: MediumInterface,
    ) -> Result<(), SceneError> {
        if motion.positions.first().map(Vec::len) != Some(mesh.positions.len()) {
            return Err(SceneError::InvalidParameter(format!(
                "a moving mesh has {} vertices but its first frame {}",
                mesh.positions.len(),
                motion.positions.first().map_or(0, Vec::len)
            )));
        }
        mesh.positions.clone_from(&motion.positions[0]);
        if let (Some(n), Some(kn)) = (&mut mesh.normals, &motion.normals) {
            n.clone_from(&kn[0]);
        }
        let b = mesh.bounds();
        let diag = (b.max - b.min).length();
        for (k, w) in motion.positions.windows(2).enumerate() {
            if let Some(i) = (0..w[0].len()).find(|&i| {
                let d = (w[1][i] - w[0][i]).length();
                d.is_nan() || d > 10.0 * diag || w[1][i].abs().max_element() > MAX_COORDINATE
            }) {
                return Err(SceneError::InvalidParameter(format!(
                    "degenerate motion: vertex {i} moves {} m between frames {k} and {} \
                     (more than 10x the mesh's size {diag} m, or beyond ±{MAX_COORDINATE:e})",
                    (w[1][i] - w[0][i]).length(),
                    k + 1
                )));
            }
        }
        if flip_normals {
            motion.flip_normals();
        }
        let before = self.shapes.len();
        self.add_shape_with_media(
            ShapeGeometry::Mesh(mesh),
            material,
            None,
            flip_normals,
            media,
        )?;
        if let Some(shape) = self.shapes.get_mut(before) {
            shape.motion = Some(std::sync::Arc::new(motion));
        }
        Ok(())
    }

    /// Sets the camera's shutter (frames; default: the instant 0).
    pub fn set_shutter(&mut self, shutter: Shutter) {
        self.shutter = shutter;
    }

    /// The camera's shutter.
    pub fn shutter(&self) -> Shutter {
        self.shutter
    }

    pub fn add_light(&mut self, light: Light) {
        self.lights.push(light);
    }

    /// Gives light `light` (its index in the order added) a named emission spectrum; its RGB
    /// values must be the spectrum's colour ([`crate::light::NamedSpectrum::rgb`]) times its
    /// scale.
    pub fn set_light_spectrum(&mut self, light: usize, spectrum: EmissionSpectrum) {
        self.light_spectra.push((light, spectrum));
    }

    pub fn set_camera(&mut self, camera: PerspectiveCamera) {
        self.camera = Some(camera);
    }

    /// Shapes added so far (read-only; for loaders' tests and tools).
    pub fn shapes(&self) -> &[Shape] {
        &self.shapes
    }
    /// Number of shapes added so far.
    pub fn shape_count(&self) -> usize {
        self.shapes.len()
    }
    /// Lights added so far (including the area lights of emitting shapes).
    pub fn lights(&self) -> &[Light] {
        &self.lights
    }
    /// The camera, if one was set.
    pub fn camera(&self) -> Option<&PerspectiveCamera> {
        self.camera.as_ref()
    }
    /// Materials added so far, in index order.
    pub fn materials(&self) -> &[Material] {
        &self.materials
    }
    /// Names of the materials, parallel to [`SceneBuilder::materials`].
    pub fn material_names(&self) -> &[String] {
        &self.material_names
    }
    /// Number of mesh triangles dropped so far by sanitising (NaN/Inf, degenerate, bad index).
    pub fn skipped_triangles(&self) -> usize {
        self.skipped_triangles
    }
    /// The warnings the built scene will carry (explicit warnings plus the skipped-triangle
    /// count).
    pub fn pending_warnings(&self) -> Vec<String> {
        let mut warnings = self.warnings.clone();
        if self.skipped_triangles > 0 {
            warnings.push(format!(
                "skipped {} triangles with NaN/Inf vertices, degenerate area or bad indices",
                self.skipped_triangles
            ));
        }
        warnings
    }

    /// Validates and builds the scene (BVH, light preprocessing, light distribution).
    pub fn build(self) -> Result<Scene, SceneError> {
        let mut warnings = self.pending_warnings();
        let camera = self
            .camera
            .ok_or_else(|| SceneError::Invalid("the scene has no camera".into()))?;
        if camera.width == 0 || camera.height == 0 {
            return Err(SceneError::InvalidParameter(format!(
                "image size must be positive, got {}x{}",
                camera.width, camera.height
            )));
        }
        let has_media = !self.media.is_empty() || self.materials.iter().any(|m| m.is_null());
        // Moving meshes keep the keyframes the shutter needs; those that do not move there
        // become static (the fast path).
        let shutter = self.shutter;
        let mut shapes = self.shapes;
        for shape in &mut shapes {
            let Some(motion) = shape.motion.take() else {
                continue;
            };
            let w = motion.window(shutter.open, shutter.close());
            if w.moves() {
                shape.motion = Some(std::sync::Arc::new(w));
            } else if let ShapeGeometry::Mesh(m) = &mut shape.geometry {
                m.positions = (0..m.positions.len())
                    .map(|i| motion.position(i, shutter.open))
                    .collect();
                if let Some(n) = &mut m.normals {
                    *n = (0..n.len())
                        .map(|i| motion.normal(i, shutter.open).unwrap_or(n[i]))
                        .collect();
                }
            }
        }
        let light_origins: Vec<Option<caustica_core::Vec3>> =
            self.lights.iter().map(|l| l.medium_probe_point()).collect();
        let geometry = Geometry::build(shapes);
        let locate = |p: Option<caustica_core::Vec3>| match p {
            Some(p) if has_media => medium_at(&geometry, p),
            _ => NONE,
        };
        let camera_medium = self
            .camera_medium
            .unwrap_or_else(|| locate(Some(camera.position())));
        let mut light_media: Vec<u32> = light_origins.iter().map(|&p| locate(p)).collect();
        for &(l, m) in &self.light_media {
            if let Some(slot) = light_media.get_mut(l) {
                *slot = m;
            }
        }
        let (center, radius) = geometry.bounds().bounding_sphere();
        let mut lights = self.lights;
        for l in &mut lights {
            l.preprocess(center, radius.max(1e-3));
        }
        let infinite_lights = lights
            .iter()
            .enumerate()
            .filter(|(_, l)| l.is_infinite())
            .map(|(i, _)| i as u32)
            .collect();
        let mut light_spectra = vec![EmissionSpectrum::Rgb; lights.len()];
        for &(l, e) in &self.light_spectra {
            if let Some(slot) = light_spectra.get_mut(l) {
                *slot = e;
            }
        }
        let powers: Vec<f32> = lights.iter().map(|l| l.power().average()).collect();
        let light_distribution = Distribution1D::new(&powers);
        if light_distribution.is_none() {
            warnings
                .push("the scene has no light with positive power; images will be black".into());
        }
        Ok(Scene {
            name: self.name,
            geometry,
            materials: self.materials,
            material_names: self.material_names,
            lights,
            camera,
            settings: self.settings,
            light_distribution,
            infinite_lights,
            warnings,
            media: self.media,
            medium_names: self.medium_names,
            camera_medium,
            light_media,
            has_media,
            shutter,
            spectral: false,
            light_spectra,
            projection: std::sync::OnceLock::new(),
        })
    }
}
