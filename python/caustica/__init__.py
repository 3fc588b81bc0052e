"""caustica from Python: renders as NumPy arrays, the metrics of ``caustica compare``, images.

A render from Python is the render of the same ``caustica render`` command line, bit for bit:
the keyword arguments of :func:`render` are the command line's options (``min_footprint=0.5``
is ``--min-footprint 0.5``) and are parsed by its own parser, so defaults, checks and error
messages are the command line's. Images are ``float32`` arrays of shape ``(height, width, 3)``
holding linear RGB radiance in W/m²/sr, row 0 at the top.

>>> import caustica
>>> scene = caustica.load("water-wave")
>>> image, notes = caustica.render(scene, integrator="pds", photons=20_000, spp=4, seed=1)
>>> image.shape, notes["integrator"]
((256, 256, 3), 'pds')
"""

from __future__ import annotations

import os
import warnings
from typing import Any, Mapping, Optional, Sequence, Tuple, Union

import numpy as np

from . import _caustica
from ._caustica import Scene

__version__: str = _caustica.__version__
__all__ = ["Scene", "load", "render", "render_options", "compare", "read", "write"]

PathLike = Union[str, "os.PathLike[str]"]


def load(scene: Optional[PathLike] = None, **defaults: Union[str, int, float, bool]) -> Scene:
    """Loads a scene: a scene file (caustica TOML, Mitsuba 3 XML, pbrt-v4) or the name of a
    built-in scene (``caustica scenes`` lists them); ``None`` is the embedded default scene.

    Keyword arguments override a Mitsuba scene's ``<default>`` parameters, as ``-D name=value``
    does on the command line (``load("scene.xml", spp=64, roughness=0.1)``).

    Raises ``OSError`` when a file cannot be read and ``ValueError`` when it is malformed, with
    the message the command line prints.
    """
    source = None if scene is None else os.fspath(scene)
    if source is not None and not isinstance(source, str):
        raise TypeError(f"load() argument 'scene' must be a str or os.PathLike, not {type(scene).__name__}")
    defines = [(name, _define_text(name, value)) for name, value in defaults.items()]
    return _caustica.load(source, defines)


def _define_text(name: str, value: Any) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, (int, float)):
        return repr(value)
    if isinstance(value, str):
        return value
    raise TypeError(f"load() argument '{name}' must be a str, int, float or bool, not {type(value).__name__}")


def render(
    scene: Union[Scene, PathLike, None],
    integrator: Optional[str] = None,
    photons: Optional[int] = None,
    spp: Optional[int] = None,
    seed: int = 0,
    threads: Optional[int] = None,
    *,
    crop: Union[Sequence[int], str, None] = None,
    **options: Any,
) -> Tuple[np.ndarray, dict]:
    """Renders ``scene`` and returns ``(image, notes)``.

    ``image`` is a ``float32`` array ``(height, width, 3)`` of linear RGB radiance (W/m²/sr),
    bit for bit the image ``caustica render`` writes to EXR for the same scene, options and
    seed. ``notes`` is a dict: ``scene``, ``integrator``, ``seconds``, ``spp`` (or
    ``light_paths`` for the light tracer; both for ``hybrid``), ``iterations``, ``samples``, ``rays``,
    ``samples_per_second``, ``rays_per_second``, ``nonfinite``, ``notes`` (what the photon
    passes and automatic bandwidths report, one string each) and ``warnings``.

    Arguments left at ``None`` take the command line's defaults (the integrator and sample
    count the scene suggests, else ``path`` and 16 spp). ``threads`` is the number of worker
    threads (default: one per core); the image does not depend on it. ``crop=(x, y, w, h)``
    renders only that window of the film (``--crop``). Every other option of
    ``caustica render`` that decides what is computed is a keyword argument: ``time=10.0``,
    ``smoothing=0.5``, ``kernel="epanechnikov"``, ``caustics_only=True``, ``width=128``,
    ``spectral=True``, … (:func:`render_options` lists them with their types).

    The GIL is released while rendering. Ctrl-C (``KeyboardInterrupt``) stops the render after
    its current pass and raises ``KeyboardInterrupt``.

    Raises ``TypeError`` for an unknown option or a value of the wrong type (naming the
    argument), ``ValueError`` for a value the command line refuses (with its message), and
    ``OSError`` for files that cannot be read.
    """
    if not isinstance(scene, Scene):
        scene = load(scene)
    kwargs = [("integrator", integrator), ("photons", photons), ("spp", spp), ("seed", seed)]
    kwargs += list(options.items())
    if threads is not None and (isinstance(threads, bool) or not isinstance(threads, int)):
        raise TypeError(f"render() argument 'threads' must be an int, not {type(threads).__name__}")
    if threads is not None and threads < 1:
        raise ValueError(f"--threads must be at least 1, got {threads}")
    data, width, height, notes = _caustica.render_image(scene, kwargs, threads, _crop_text(crop))
    for w in notes["warnings"]:
        warnings.warn(w, stacklevel=2)
    image = np.frombuffer(data, dtype="<f4").reshape(height, width, 3)
    return image, notes


def _crop_text(crop: Union[Sequence[int], str, None]) -> Optional[str]:
    if crop is None or isinstance(crop, str):
        return crop
    try:
        values = list(crop)
    except TypeError:
        raise TypeError(f"render() argument 'crop' must be (x, y, w, h) or 'X,Y,W,H', not {type(crop).__name__}") from None
    if len(values) != 4 or not all(isinstance(v, (int, np.integer)) and not isinstance(v, bool) for v in values):
        raise TypeError(f"render() argument 'crop' must be four ints (x, y, w, h), got {crop!r}")
    return ",".join(str(int(v)) for v in values)


def render_options() -> Mapping[str, str]:
    """The keyword options of :func:`render` (the command line's render options, ``-`` written
    ``_``) and the Python type each takes: ``bool``, ``int``, ``float``, ``str`` or ``list``."""
    return dict(_caustica.render_options())


def _image(name: str, image: Any, mask: bool = False) -> Tuple[bytes, int, int]:
    """An image argument as float32 RGB bytes, width, height."""
    if isinstance(image, (str, bytes, os.PathLike)) or image is None:
        raise TypeError(f"argument '{name}' must be an array (height, width, 3), not {type(image).__name__}")
    try:
        a = np.asarray(image, dtype=np.float32)
    except (TypeError, ValueError) as e:
        raise TypeError(f"argument '{name}' must be an array of numbers (height, width, 3): {e}") from None
    if mask and a.ndim == 2:
        a = np.repeat(a[:, :, None], 3, axis=2)
    if a.ndim != 3 or a.shape[2] != 3:
        shape = "(height, width) or (height, width, 3)" if mask else "(height, width, 3)"
        raise ValueError(f"argument '{name}' must have shape {shape}, got {a.shape}")
    a = np.ascontiguousarray(a, dtype="<f4")
    return a.tobytes(), a.shape[1], a.shape[0]


def compare(
    image: Any,
    reference: Any,
    mask: Any = None,
    crop: Union[Sequence[int], str, None] = None,
    *,
    exposure: float = 0.0,
    block: int = 16,
    block_tolerance: float = 0.01,
    mask_black: bool = False,
) -> dict:
    """The metrics of ``caustica compare`` for ``image`` against ``reference`` (arrays of the
    same size): ``pixels``, ``mean_image``, ``mean_reference``, ``relative_mean_difference``,
    ``rmse``, ``relative_mse``, ``mise``, ``ssim`` (``None`` if the region is narrower than
    the 11-pixel window), ``pixel_z`` and ``block_z`` (the noise-versus-bias tests, dicts).

    ``mask``: an array of the image's size; only pixels where it is non-zero count. ``crop``:
    ``(x, y, w, h)``. ``exposure``: the display transform of MISE and SSIM (stops).
    ``mask_black``: ignore pixels black in both images. ``block``, ``block_tolerance``: the
    regional bias test's block side and smallest reported relative difference.
    """
    m = None if mask is None else _image("mask", mask, mask=True)
    return _caustica.compare_images(
        _image("image", image),
        _image("reference", reference),
        m,
        _crop_text(crop),
        float(exposure),
        int(block),
        float(block_tolerance),
        bool(mask_black),
    )


def read(path: PathLike) -> np.ndarray:
    """Reads an EXR, PFM or PNG image (PNG decoded from sRGB to linear) as a ``float32`` array
    ``(height, width, 3)``. Raises ``OSError`` if it cannot be read, with the CLI's message."""
    data, width, height = _caustica.read_image(os.fspath(path))
    return np.frombuffer(data, dtype="<f4").reshape(height, width, 3)


def write(path: PathLike, image: Any, *, exposure: float = 0.0) -> None:
    """Writes an image array ``(height, width, 3)`` as EXR or PFM (32-bit float) or PNG (sRGB,
    tone-mapped at ``exposure`` stops as ``caustica render --png`` does), by extension."""
    data, width, height = _image("image", image)
    _caustica.write_image(os.fspath(path), data, width, height, float(exposure))
