import os
from typing import Any, Callable, Dict, List, Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

from ._glview import BusyError as BusyError
from ._glview import ContextError as ContextError
from ._glview import GlviewError as GlviewError
from ._glview import ModelError as ModelError
from ._glview import OptionError as OptionError
from ._glview import options_words as options_words

__version__: str

Model = Union[str, "os.PathLike[str]", Tuple[Any, Any], Dict[str, Any], Any]

class Image:
    color: npt.NDArray[np.uint8]
    text: List[Tuple[str, str]]
    depth: Optional[npt.NDArray[np.float32]]
    normals: Optional[npt.NDArray[np.float32]]
    object_ids: Optional[npt.NDArray[np.int32]]
    material_ids: Optional[npt.NDArray[np.int32]]
    linear: Optional[npt.NDArray[np.float32]]
    object_names: List[str]
    material_names: List[str]
    stats: Dict[str, Any]
    def __init__(
        self,
        color: npt.NDArray[np.uint8],
        text: Optional[List[Tuple[str, str]]] = ...,
        depth: Optional[npt.NDArray[np.float32]] = ...,
        normals: Optional[npt.NDArray[np.float32]] = ...,
        object_ids: Optional[npt.NDArray[np.int32]] = ...,
        material_ids: Optional[npt.NDArray[np.int32]] = ...,
        linear: Optional[npt.NDArray[np.float32]] = ...,
        object_names: Sequence[str] = ...,
        material_names: Sequence[str] = ...,
        stats: Optional[Dict[str, Any]] = ...,
    ) -> None: ...
    @property
    def rgb(self) -> npt.NDArray[np.uint8]: ...
    @property
    def width(self) -> int: ...
    @property
    def height(self) -> int: ...
    def png(self) -> bytes: ...
    def _repr_png_(self) -> bytes: ...
    def save(self, path: Union[str, "os.PathLike[str]"]) -> None: ...

class Renderer:
    def __init__(self, width: int = ..., height: int = ..., **options: Any) -> None: ...
    def load(self, model: Model, **options: Any) -> "Renderer": ...
    def render(
        self,
        *,
        depth: bool = ...,
        normals: bool = ...,
        ids: bool = ...,
        linear: bool = ...,
        eyes: bool = ...,
        **options: Any,
    ) -> Any: ...
    def hold(self, callback: Callable[[], Any]) -> None: ...
    def close(self) -> None: ...
    def __enter__(self) -> "Renderer": ...
    def __exit__(self, *exc: Any) -> None: ...

def render(
    model: Optional[Model] = ...,
    *,
    depth: bool = ...,
    normals: bool = ...,
    ids: bool = ...,
    linear: bool = ...,
    eyes: bool = ...,
    **options: Any,
) -> Any: ...
def release() -> None: ...
def diff(
    a: Union[Image, npt.NDArray[np.uint8]], b: Union[Image, npt.NDArray[np.uint8]]
) -> Tuple[Image, Dict[str, Any]]: ...
def diff_tiers(
    model: Union[str, "os.PathLike[str]", None] = ..., tiers: str = ..., **options: Any
) -> Tuple[Image, Dict[str, Any]]: ...
def compare(
    model: Union[str, "os.PathLike[str]", None] = ..., tiers: str = ..., **options: Any
) -> Image: ...
def export(
    model: Union[str, "os.PathLike[str]", None],
    path: Union[str, "os.PathLike[str]"],
    yaw_steps: int = ...,
    pitch_steps: int = ...,
    pitch_step: float = ...,
    quality: int = ...,
    png: bool = ...,
    title: Optional[str] = ...,
    caption: Optional[str] = ...,
    max_size: Optional[int] = ...,
    scorm: Union[str, "os.PathLike[str]", None] = ...,
    **options: Any,
) -> Dict[str, Any]: ...
def sheet(
    model: Union[str, "os.PathLike[str]", None] = ...,
    tiers: str = ...,
    views: int = ...,
    angles: Optional[str] = ...,
    **options: Any,
) -> Image: ...
