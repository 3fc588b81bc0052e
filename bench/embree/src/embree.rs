//! A small safe layer over [`crate::ffi`]: a device, a committed triangle scene, and the
//! closest-hit and occlusion queries the benchmark times (single rays, 8-ray packets, 1M
//! streams). Only what the benchmark needs.

use std::ffi::{CStr, CString, c_uint};
use std::marker::PhantomData;
use std::ptr::NonNull;

use caustica_core::{Ray, Vec3};

use crate::ffi::*;

/// Build quality of a scene.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Quality {
    Medium,
    High,
}

impl Quality {
    pub fn name(self) -> &'static str {
        match self {
            Quality::Medium => "MEDIUM",
            Quality::High => "HIGH",
        }
    }
    fn raw(self) -> RTCBuildQuality {
        match self {
            Quality::Medium => RTC_BUILD_QUALITY_MEDIUM,
            Quality::High => RTC_BUILD_QUALITY_HIGH,
        }
    }
}

/// The coherence hint of an intersection context.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Coherence {
    Coherent,
    Incoherent,
}

fn context(c: Coherence) -> RTCIntersectContext {
    let mut ctx = RTCIntersectContext::new();
    ctx.flags = match c {
        Coherence::Coherent => RTC_INTERSECT_CONTEXT_FLAG_COHERENT,
        Coherence::Incoherent => RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT,
    };
    ctx
}

/// An Embree device (owned reference, released on drop).
pub struct Device {
    raw: NonNull<RTCDeviceTy>,
}

impl Device {
    /// A device with Embree's configuration string `config` (`None`: the default
    /// configuration, as `rtcNewDevice(NULL)`).
    pub fn new(config: Option<&str>) -> Result<Self, String> {
        let config = config
            .map(CString::new)
            .transpose()
            .map_err(|e| e.to_string())?;
        let ptr = config.as_deref().map_or(std::ptr::null(), CStr::as_ptr);
        // SAFETY: `ptr` is NULL (allowed: the default configuration) or points to a
        // NUL-terminated string that `config` keeps alive for the duration of the call; Embree
        // does not keep the pointer. The result is checked for NULL before use.
        let raw = unsafe { rtcNewDevice(ptr) };
        match NonNull::new(raw) {
            Some(raw) => Ok(Self { raw }),
            None => {
                // SAFETY: a NULL device is allowed here; it returns the error of the last
                // device creation on this thread.
                let code = unsafe { rtcGetDeviceError(std::ptr::null_mut()) };
                Err(format!("rtcNewDevice failed (RTCError {code})"))
            }
        }
    }

    /// `rtcGetDeviceProperty`.
    pub fn property(&self, prop: RTCDeviceProperty) -> isize {
        // SAFETY: `self.raw` is a live device (owned by `self`); an unknown property only sets
        // the device's error code.
        unsafe { rtcGetDeviceProperty(self.raw.as_ptr(), prop) }
    }

    /// The error message of a call that returned NULL.
    fn failed(&self, what: &str) -> String {
        self.check(what)
            .err()
            .unwrap_or_else(|| format!("{what} returned NULL"))
    }

    fn check(&self, what: &str) -> Result<(), String> {
        // SAFETY: `self.raw` is a live device; reading its error code has no other effect.
        let code = unsafe { rtcGetDeviceError(self.raw.as_ptr()) };
        if code == RTC_ERROR_NONE {
            Ok(())
        } else {
            Err(format!("{what}: Embree error {code}"))
        }
    }
}

impl Drop for Device {
    fn drop(&mut self) {
        // SAFETY: `self.raw` holds one reference, released exactly once here. Scenes borrow the
        // device (`Scene<'d>`), so none outlives it on the Rust side (Embree's own scenes hold a
        // reference of their own anyway).
        unsafe { rtcReleaseDevice(self.raw.as_ptr()) }
    }
}

/// A committed scene holding one triangle mesh (owned reference, released on drop).
pub struct Scene<'d> {
    raw: NonNull<RTCSceneTy>,
    _device: PhantomData<&'d Device>,
}

impl<'d> Scene<'d> {
    /// Builds (commits) a scene of one triangle mesh with the given quality and scene flags.
    /// The vertex and index data are copied into buffers Embree allocates (and pads as it
    /// requires).
    pub fn build(
        device: &'d Device,
        positions: &[Vec3],
        indices: &[[u32; 3]],
        quality: Quality,
        flags: RTCSceneFlags,
    ) -> Result<Self, String> {
        let dev = device.raw.as_ptr();
        // SAFETY: `dev` is a live device. Each returned handle is checked for NULL before use.
        let scene = NonNull::new(unsafe { rtcNewScene(dev) })
            .ok_or_else(|| device.failed("rtcNewScene"))?;
        // From here on `scene` is released by `Scene`'s drop on every path.
        let scene = Scene {
            raw: scene,
            _device: PhantomData,
        };
        // SAFETY: `scene.raw` is a live, uncommitted scene; quality and flags are valid values
        // of their C enums.
        unsafe {
            rtcSetSceneBuildQuality(scene.raw.as_ptr(), quality.raw());
            rtcSetSceneFlags(scene.raw.as_ptr(), flags);
        }
        // SAFETY: `dev` is live and `RTC_GEOMETRY_TYPE_TRIANGLE` a valid geometry type.
        let geom = unsafe { rtcNewGeometry(dev, RTC_GEOMETRY_TYPE_TRIANGLE) };
        if geom.is_null() {
            return Err(device.failed("rtcNewGeometry"));
        }
        // SAFETY: `geom` is a live triangle geometry. `rtcSetNewGeometryBuffer` returns a
        // buffer of at least `item_count · byte_stride` bytes (16-byte aligned, padded by
        // Embree), or NULL on failure (checked). The buffers are owned by the geometry, which
        // lives until `rtcReleaseGeometry` below — after the scene has taken its own reference
        // in `rtcAttachGeometry` — so the slices made from them are used only while they are
        // valid and nothing else aliases them. `[f32; 3]` and `[u32; 3]` have size 12 (the
        // stride passed) and alignment 4 ≤ 16. `geom` is released exactly once on every path.
        unsafe {
            let vb = rtcSetNewGeometryBuffer(
                geom,
                RTC_BUFFER_TYPE_VERTEX,
                0,
                RTC_FORMAT_FLOAT3,
                12,
                positions.len(),
            ) as *mut [f32; 3];
            let ib = rtcSetNewGeometryBuffer(
                geom,
                RTC_BUFFER_TYPE_INDEX,
                0,
                RTC_FORMAT_UINT3,
                12,
                indices.len(),
            ) as *mut [u32; 3];
            if vb.is_null() || ib.is_null() {
                rtcReleaseGeometry(geom);
                return Err(device.failed("rtcSetNewGeometryBuffer"));
            }
            let vs = std::slice::from_raw_parts_mut(vb, positions.len());
            for (v, p) in vs.iter_mut().zip(positions) {
                *v = p.to_array();
            }
            std::slice::from_raw_parts_mut(ib, indices.len()).copy_from_slice(indices);
            rtcCommitGeometry(geom);
            rtcAttachGeometry(scene.raw.as_ptr(), geom);
            rtcReleaseGeometry(geom);
            rtcCommitScene(scene.raw.as_ptr());
        }
        device.check("rtcCommitScene")?;
        Ok(scene)
    }

    /// Closest hit distance of `r` (`rtcIntersect1`), or `None` on a miss.
    #[inline]
    pub fn intersect1(&self, coherence: Coherence, r: &Ray) -> Option<f32> {
        let mut ctx = context(coherence);
        let mut rh = RTCRayHit {
            ray: rtc_ray(r),
            hit: RTCHit {
                geomID: RTC_INVALID_GEOMETRY_ID,
                instID: [RTC_INVALID_GEOMETRY_ID; RTC_MAX_INSTANCE_LEVEL_COUNT],
                ..RTCHit::default()
            },
        };
        // SAFETY: the scene is committed and not modified afterwards (no `&mut` method exists);
        // `ctx` is initialised as `rtcInitIntersectContext` does and `rh` is a valid, 16-byte
        // aligned `RTCRayHit` (its type's alignment); both live across the call, which does not
        // keep the pointers.
        unsafe { rtcIntersect1(self.raw.as_ptr(), &mut ctx, &mut rh) };
        (rh.hit.geomID != RTC_INVALID_GEOMETRY_ID).then_some(rh.ray.tfar)
    }

    /// True if anything blocks `r` before `r.t_max` (`rtcOccluded1`).
    #[inline]
    pub fn occluded1(&self, coherence: Coherence, r: &Ray) -> bool {
        let mut ctx = context(coherence);
        let mut ray = rtc_ray(r);
        // SAFETY: as in `intersect1`: committed scene, initialised context, an aligned `RTCRay`
        // that outlives the call.
        unsafe { rtcOccluded1(self.raw.as_ptr(), &mut ctx, &mut ray) };
        ray.tfar == f32::NEG_INFINITY
    }

    /// Closest hits of up to eight rays as one packet (`rtcIntersect8`); `None` lanes are
    /// inactive and return `None`.
    #[inline]
    pub fn intersect8(&self, coherence: Coherence, lanes: [Option<&Ray>; 8]) -> [Option<f32>; 8] {
        let mut ctx = context(coherence);
        let mut valid = Valid8::default();
        let mut rh = RTCRayHit8::default();
        for (l, r) in lanes.iter().enumerate() {
            let Some(r) = r else { continue };
            valid.0[l] = -1;
            set_lane(&mut rh.ray, l, r);
            rh.hit.geomID[l] = RTC_INVALID_GEOMETRY_ID;
            rh.hit.instID[0][l] = RTC_INVALID_GEOMETRY_ID;
        }
        // SAFETY: committed scene; `valid` and `rh` are 32-byte aligned (their types'
        // alignment, as Embree requires of both), fully initialised (inactive lanes are zero
        // and masked off by `valid`), and live across the call; `ctx` is initialised as
        // `rtcInitIntersectContext` does.
        unsafe { rtcIntersect8(&valid, self.raw.as_ptr(), &mut ctx, &mut rh) };
        std::array::from_fn(|l| {
            (valid.0[l] != 0 && rh.hit.geomID[l] != RTC_INVALID_GEOMETRY_ID)
                .then_some(rh.ray.tfar[l])
        })
    }

    /// Occlusion of up to eight rays as one packet (`rtcOccluded8`); inactive lanes are false.
    #[inline]
    pub fn occluded8(&self, coherence: Coherence, lanes: [Option<&Ray>; 8]) -> [bool; 8] {
        let mut ctx = context(coherence);
        let mut valid = Valid8::default();
        let mut ray = RTCRay8::default();
        for (l, r) in lanes.iter().enumerate() {
            let Some(r) = r else { continue };
            valid.0[l] = -1;
            set_lane(&mut ray, l, r);
        }
        // SAFETY: as in `intersect8`, with an aligned, initialised `RTCRay8`.
        unsafe { rtcOccluded8(&valid, self.raw.as_ptr(), &mut ctx, &mut ray) };
        std::array::from_fn(|l| valid.0[l] != 0 && ray.tfar[l] == f32::NEG_INFINITY)
    }

    /// Closest hits of a stream of rays (`rtcIntersect1M`, array of structures), written to
    /// `out` (same length as `rays`); `buf` is scratch space reused between calls.
    pub fn intersect1m(
        &self,
        coherence: Coherence,
        rays: &[&Ray],
        buf: &mut Vec<RTCRayHit>,
        out: &mut [Option<f32>],
    ) {
        assert_eq!(rays.len(), out.len());
        let m = c_uint::try_from(rays.len()).expect("stream too long");
        let mut ctx = context(coherence);
        buf.clear();
        buf.extend(rays.iter().map(|r| RTCRayHit {
            ray: rtc_ray(r),
            hit: RTCHit {
                geomID: RTC_INVALID_GEOMETRY_ID,
                instID: [RTC_INVALID_GEOMETRY_ID; RTC_MAX_INSTANCE_LEVEL_COUNT],
                ..RTCHit::default()
            },
        }));
        // SAFETY: committed scene; `buf` holds exactly `m` initialised, 16-byte aligned
        // `RTCRayHit`s (a `Vec` aligns to its element type) laid out `size_of::<RTCRayHit>()`
        // bytes apart, the stride passed; Embree writes only inside them and keeps no pointer.
        unsafe {
            rtcIntersect1M(
                self.raw.as_ptr(),
                &mut ctx,
                buf.as_mut_ptr(),
                m,
                size_of::<RTCRayHit>(),
            )
        };
        for (o, rh) in out.iter_mut().zip(buf.iter()) {
            *o = (rh.hit.geomID != RTC_INVALID_GEOMETRY_ID).then_some(rh.ray.tfar);
        }
    }

    /// Occlusion of a stream of rays (`rtcOccluded1M`), written to `out`.
    pub fn occluded1m(
        &self,
        coherence: Coherence,
        rays: &[&Ray],
        buf: &mut Vec<RTCRay>,
        out: &mut [bool],
    ) {
        assert_eq!(rays.len(), out.len());
        let m = c_uint::try_from(rays.len()).expect("stream too long");
        let mut ctx = context(coherence);
        buf.clear();
        buf.extend(rays.iter().map(|r| rtc_ray(r)));
        // SAFETY: as in `intersect1m`, with `m` initialised, aligned `RTCRay`s.
        unsafe {
            rtcOccluded1M(
                self.raw.as_ptr(),
                &mut ctx,
                buf.as_mut_ptr(),
                m,
                size_of::<RTCRay>(),
            )
        };
        for (o, r) in out.iter_mut().zip(buf.iter()) {
            *o = r.tfar == f32::NEG_INFINITY;
        }
    }
}

impl Drop for Scene<'_> {
    fn drop(&mut self) {
        // SAFETY: `self.raw` holds one reference, released exactly once here; no query can run
        // concurrently (the queries borrow `self`).
        unsafe { rtcReleaseScene(self.raw.as_ptr()) }
    }
}

/// A caustica ray as Embree's: `t ∈ [0, t_max]`, every mask bit set.
#[inline(always)]
fn rtc_ray(r: &Ray) -> RTCRay {
    RTCRay {
        org_x: r.o.x,
        org_y: r.o.y,
        org_z: r.o.z,
        tnear: 0.0,
        dir_x: r.d.x,
        dir_y: r.d.y,
        dir_z: r.d.z,
        time: 0.0,
        tfar: r.t_max,
        mask: u32::MAX,
        id: 0,
        flags: 0,
    }
}

#[inline(always)]
fn set_lane(p: &mut RTCRay8, l: usize, r: &Ray) {
    p.org_x[l] = r.o.x;
    p.org_y[l] = r.o.y;
    p.org_z[l] = r.o.z;
    p.tnear[l] = 0.0;
    p.dir_x[l] = r.d.x;
    p.dir_y[l] = r.d.y;
    p.dir_z[l] = r.d.z;
    p.time[l] = 0.0;
    p.tfar[l] = r.t_max;
    p.mask[l] = u32::MAX;
    p.id[l] = l as u32;
    p.flags[l] = 0;
}
