//! Hand-written bindings to the few parts of Embree 3's C API (3.13.5, Debian's `libembree-dev`)
//! that the benchmark uses. Every type mirrors `/usr/include/embree3/*.h` field for field, with
//! the header's `RTC_ALIGN`; the layout test at the bottom pins sizes, alignments and offsets
//! (the numbers were read off the headers and checked against a C compiler's `sizeof`,
//! `_Alignof` and `offsetof` on the installed headers).
//!
//! The installed `rtcore_config.h` sets `RTC_MAX_INSTANCE_LEVEL_COUNT 1` and `RTC_MIN_WIDTH 0`,
//! which fixes the shapes of `RTCHit*::instID` and `RTCIntersectContext`.
//!
//! C enums are plain `int`/`unsigned`-sized values here (`u32` aliases with constants), so no
//! value Embree returns can be an invalid Rust enum.

#![allow(non_camel_case_types, non_snake_case)]

use std::ffi::{c_char, c_uint, c_void};

/// `RTC_MAX_INSTANCE_LEVEL_COUNT` of the installed `rtcore_config.h`.
pub const RTC_MAX_INSTANCE_LEVEL_COUNT: usize = 1;
/// `RTC_INVALID_GEOMETRY_ID`.
pub const RTC_INVALID_GEOMETRY_ID: c_uint = u32::MAX;

/// Opaque handle types (`typedef struct RTCDeviceTy* RTCDevice;` and friends).
#[repr(C)]
pub struct RTCDeviceTy {
    _opaque: [u8; 0],
}
#[repr(C)]
pub struct RTCSceneTy {
    _opaque: [u8; 0],
}
#[repr(C)]
pub struct RTCGeometryTy {
    _opaque: [u8; 0],
}
pub type RTCDevice = *mut RTCDeviceTy;
pub type RTCScene = *mut RTCSceneTy;
pub type RTCGeometry = *mut RTCGeometryTy;

/// `enum RTCDeviceProperty` (only the values queried).
pub type RTCDeviceProperty = u32;
pub const RTC_DEVICE_PROPERTY_VERSION: RTCDeviceProperty = 0;
pub const RTC_DEVICE_PROPERTY_NATIVE_RAY4_SUPPORTED: RTCDeviceProperty = 32;
pub const RTC_DEVICE_PROPERTY_NATIVE_RAY8_SUPPORTED: RTCDeviceProperty = 33;
pub const RTC_DEVICE_PROPERTY_NATIVE_RAY16_SUPPORTED: RTCDeviceProperty = 34;
pub const RTC_DEVICE_PROPERTY_RAY_STREAM_SUPPORTED: RTCDeviceProperty = 35;
pub const RTC_DEVICE_PROPERTY_BACKFACE_CULLING_ENABLED: RTCDeviceProperty = 65;
pub const RTC_DEVICE_PROPERTY_TASKING_SYSTEM: RTCDeviceProperty = 128;

/// `enum RTCError`.
pub type RTCError = u32;
pub const RTC_ERROR_NONE: RTCError = 0;

/// `enum RTCGeometryType` (only triangles).
pub type RTCGeometryType = u32;
pub const RTC_GEOMETRY_TYPE_TRIANGLE: RTCGeometryType = 0;

/// `enum RTCBufferType`.
pub type RTCBufferType = u32;
pub const RTC_BUFFER_TYPE_INDEX: RTCBufferType = 0;
pub const RTC_BUFFER_TYPE_VERTEX: RTCBufferType = 1;

/// `enum RTCFormat` (only the two used).
pub type RTCFormat = u32;
pub const RTC_FORMAT_UINT3: RTCFormat = 0x5003;
pub const RTC_FORMAT_FLOAT3: RTCFormat = 0x9003;

/// `enum RTCBuildQuality`.
pub type RTCBuildQuality = u32;
pub const RTC_BUILD_QUALITY_MEDIUM: RTCBuildQuality = 1;
pub const RTC_BUILD_QUALITY_HIGH: RTCBuildQuality = 2;

/// `enum RTCSceneFlags`.
pub type RTCSceneFlags = u32;
pub const RTC_SCENE_FLAG_NONE: RTCSceneFlags = 0;
pub const RTC_SCENE_FLAG_ROBUST: RTCSceneFlags = 1 << 2;

/// `enum RTCIntersectContextFlags`.
pub type RTCIntersectContextFlags = u32;
pub const RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT: RTCIntersectContextFlags = 0;
pub const RTC_INTERSECT_CONTEXT_FLAG_COHERENT: RTCIntersectContextFlags = 1;

/// `RTCFilterFunctionN`; its argument struct is never built here, so it is left opaque.
pub type RTCFilterFunctionN = Option<unsafe extern "C" fn(args: *const c_void)>;

/// `struct RTCIntersectContext` with `RTC_MAX_INSTANCE_LEVEL_COUNT == 1` (no `instStackSize`)
/// and `RTC_MIN_WIDTH == 0` (no `minWidthDistanceFactor`).
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct RTCIntersectContext {
    pub flags: RTCIntersectContextFlags,
    pub filter: RTCFilterFunctionN,
    pub instID: [c_uint; RTC_MAX_INSTANCE_LEVEL_COUNT],
}

impl RTCIntersectContext {
    /// What the header's inline `rtcInitIntersectContext` does: incoherent, no filter, every
    /// instance level `RTC_INVALID_GEOMETRY_ID` (the `instStackSize` and
    /// `minWidthDistanceFactor` fields do not exist in this configuration).
    pub fn new() -> Self {
        Self {
            flags: RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT,
            filter: None,
            instID: [RTC_INVALID_GEOMETRY_ID; RTC_MAX_INSTANCE_LEVEL_COUNT],
        }
    }
}

/// `struct RTC_ALIGN(16) RTCRay`.
#[repr(C, align(16))]
#[derive(Clone, Copy, Debug, Default)]
pub struct RTCRay {
    pub org_x: f32,
    pub org_y: f32,
    pub org_z: f32,
    pub tnear: f32,
    pub dir_x: f32,
    pub dir_y: f32,
    pub dir_z: f32,
    pub time: f32,
    pub tfar: f32,
    pub mask: c_uint,
    pub id: c_uint,
    pub flags: c_uint,
}

/// `struct RTC_ALIGN(16) RTCHit`.
#[repr(C, align(16))]
#[derive(Clone, Copy, Debug, Default)]
pub struct RTCHit {
    pub Ng_x: f32,
    pub Ng_y: f32,
    pub Ng_z: f32,
    pub u: f32,
    pub v: f32,
    pub primID: c_uint,
    pub geomID: c_uint,
    pub instID: [c_uint; RTC_MAX_INSTANCE_LEVEL_COUNT],
}

/// `struct RTCRayHit` (alignment 16 from its members).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default)]
pub struct RTCRayHit {
    pub ray: RTCRay,
    pub hit: RTCHit,
}

/// `struct RTC_ALIGN(32) RTCRay8`: eight rays, structure of arrays.
#[repr(C, align(32))]
#[derive(Clone, Copy, Debug, Default)]
pub struct RTCRay8 {
    pub org_x: [f32; 8],
    pub org_y: [f32; 8],
    pub org_z: [f32; 8],
    pub tnear: [f32; 8],
    pub dir_x: [f32; 8],
    pub dir_y: [f32; 8],
    pub dir_z: [f32; 8],
    pub time: [f32; 8],
    pub tfar: [f32; 8],
    pub mask: [c_uint; 8],
    pub id: [c_uint; 8],
    pub flags: [c_uint; 8],
}

/// `struct RTC_ALIGN(32) RTCHit8`.
#[repr(C, align(32))]
#[derive(Clone, Copy, Debug, Default)]
pub struct RTCHit8 {
    pub Ng_x: [f32; 8],
    pub Ng_y: [f32; 8],
    pub Ng_z: [f32; 8],
    pub u: [f32; 8],
    pub v: [f32; 8],
    pub primID: [c_uint; 8],
    pub geomID: [c_uint; 8],
    pub instID: [[c_uint; 8]; RTC_MAX_INSTANCE_LEVEL_COUNT],
}

/// `struct RTCRayHit8` (alignment 32 from its members).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default)]
pub struct RTCRayHit8 {
    pub ray: RTCRay8,
    pub hit: RTCHit8,
}

/// The `valid` mask of `rtcIntersect8` / `rtcOccluded8`: −1 for an active lane, 0 for an
/// inactive one. Embree reads it as one 32-byte vector (its debug build rejects a mask "not
/// aligned to 32 bytes"), hence the alignment.
#[repr(C, align(32))]
#[derive(Clone, Copy, Debug, Default)]
pub struct Valid8(pub [i32; 8]);

#[link(name = "embree3")]
unsafe extern "C" {
    pub fn rtcNewDevice(config: *const c_char) -> RTCDevice;
    pub fn rtcReleaseDevice(device: RTCDevice);
    pub fn rtcGetDeviceProperty(device: RTCDevice, prop: RTCDeviceProperty) -> isize;
    pub fn rtcGetDeviceError(device: RTCDevice) -> RTCError;

    pub fn rtcNewScene(device: RTCDevice) -> RTCScene;
    pub fn rtcReleaseScene(scene: RTCScene);
    pub fn rtcSetSceneBuildQuality(scene: RTCScene, quality: RTCBuildQuality);
    pub fn rtcSetSceneFlags(scene: RTCScene, flags: RTCSceneFlags);
    pub fn rtcAttachGeometry(scene: RTCScene, geometry: RTCGeometry) -> c_uint;
    pub fn rtcCommitScene(scene: RTCScene);

    pub fn rtcNewGeometry(device: RTCDevice, ty: RTCGeometryType) -> RTCGeometry;
    pub fn rtcSetNewGeometryBuffer(
        geometry: RTCGeometry,
        ty: RTCBufferType,
        slot: c_uint,
        format: RTCFormat,
        byte_stride: usize,
        item_count: usize,
    ) -> *mut c_void;
    pub fn rtcCommitGeometry(geometry: RTCGeometry);
    pub fn rtcReleaseGeometry(geometry: RTCGeometry);

    pub fn rtcIntersect1(
        scene: RTCScene,
        context: *mut RTCIntersectContext,
        rayhit: *mut RTCRayHit,
    );
    pub fn rtcOccluded1(scene: RTCScene, context: *mut RTCIntersectContext, ray: *mut RTCRay);
    pub fn rtcIntersect8(
        valid: *const Valid8,
        scene: RTCScene,
        context: *mut RTCIntersectContext,
        rayhit: *mut RTCRayHit8,
    );
    pub fn rtcOccluded8(
        valid: *const Valid8,
        scene: RTCScene,
        context: *mut RTCIntersectContext,
        ray: *mut RTCRay8,
    );
    pub fn rtcIntersect1M(
        scene: RTCScene,
        context: *mut RTCIntersectContext,
        rayhit: *mut RTCRayHit,
        m: c_uint,
        byte_stride: usize,
    );
    pub fn rtcOccluded1M(
        scene: RTCScene,
        context: *mut RTCIntersectContext,
        ray: *mut RTCRay,
        m: c_uint,
        byte_stride: usize,
    );
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::mem::{align_of, offset_of, size_of};

    /// Sizes, alignments and offsets of the installed headers (x86-64 Linux, GCC).
    #[test]
    fn layouts_match_the_headers() {
        assert_eq!((size_of::<RTCRay>(), align_of::<RTCRay>()), (48, 16));
        assert_eq!(offset_of!(RTCRay, tfar), 32);
        assert_eq!(offset_of!(RTCRay, mask), 36);
        assert_eq!(offset_of!(RTCRay, flags), 44);
        assert_eq!((size_of::<RTCHit>(), align_of::<RTCHit>()), (32, 16));
        assert_eq!(offset_of!(RTCHit, primID), 20);
        assert_eq!(offset_of!(RTCHit, geomID), 24);
        assert_eq!(offset_of!(RTCHit, instID), 28);
        assert_eq!((size_of::<RTCRayHit>(), align_of::<RTCRayHit>()), (80, 16));
        assert_eq!(offset_of!(RTCRayHit, hit), 48);

        assert_eq!((size_of::<RTCRay8>(), align_of::<RTCRay8>()), (384, 32));
        assert_eq!(offset_of!(RTCRay8, tfar), 256);
        assert_eq!((size_of::<RTCHit8>(), align_of::<RTCHit8>()), (256, 32));
        assert_eq!(offset_of!(RTCHit8, primID), 160);
        assert_eq!(offset_of!(RTCHit8, geomID), 192);
        assert_eq!(
            (size_of::<RTCRayHit8>(), align_of::<RTCRayHit8>()),
            (640, 32)
        );
        assert_eq!(offset_of!(RTCRayHit8, hit), 384);
        assert_eq!((size_of::<Valid8>(), align_of::<Valid8>()), (32, 32));

        assert_eq!(
            (
                size_of::<RTCIntersectContext>(),
                align_of::<RTCIntersectContext>()
            ),
            (24, 8)
        );
        assert_eq!(offset_of!(RTCIntersectContext, filter), 8);
        assert_eq!(offset_of!(RTCIntersectContext, instID), 16);
        // The filter pointer is a nullable function pointer: `None` is C's NULL.
        assert_eq!(size_of::<RTCFilterFunctionN>(), size_of::<*const c_void>());
    }
}
