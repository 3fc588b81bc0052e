import os
from typing import Any, Mapping, Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

PathLike = Union[str, os.PathLike[str]]
ImageLike = npt.ArrayLike

__version__: str

class Scene:
    """A loaded scene (see :func:`load`)."""
    @property
    def name(self) -> str: ...
    @property
    def source(self) -> Optional[str]: ...
    @property
    def width(self) -> int: ...
    @property
    def height(self) -> int: ...
    @property
    def integrator(self) -> Optional[str]: ...
    @property
    def spp(self) -> Optional[int]: ...
    @property
    def defaults(self) -> list[Tuple[str, str]]: ...
    @property
    def warnings(self) -> list[str]: ...

def load(scene: Optional[PathLike] = None, **defaults: Union[str, int, float, bool]) -> Scene:
    """Loads a scene file (TOML, Mitsuba 3 XML, pbrt-v4) or built-in scene; keyword arguments
    override Mitsuba ``<default>`` parameters (``-D name=value``)."""
    ...

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
) -> Tuple[npt.NDArray[np.float32], dict[str, Any]]:
    """Renders ``scene``: ``(image, notes)``, image a float32 (height, width, 3) array of
    radiance (W/m²/sr), bit for bit the CLI's EXR for the same options and seed."""
    ...

def render_options() -> Mapping[str, str]:
    """The keyword options of :func:`render` and their Python types."""
    ...

def compare(
    image: ImageLike,
    reference: ImageLike,
    mask: Optional[ImageLike] = None,
    crop: Union[Sequence[int], str, None] = None,
    *,
    exposure: float = 0.0,
    block: int = 16,
    block_tolerance: float = 0.01,
    mask_black: bool = False,
) -> dict[str, Any]:
    """The metrics of ``caustica compare`` as a dict."""
    ...

def read(path: PathLike) -> npt.NDArray[np.float32]:
    """Reads an EXR, PFM or PNG image as float32 (height, width, 3) linear RGB."""
    ...

def write(path: PathLike, image: ImageLike, *, exposure: float = 0.0) -> None:
    """Writes an image as EXR, PFM or PNG (by extension)."""
    ...
