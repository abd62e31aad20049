"""glview from Python: render models to NumPy arrays.

    >>> import glview
    >>> img = glview.render("bunny.obj", size=(640, 480), yaw=30, depth=True)
    >>> img.color.shape, img.depth.shape      # (480, 640, 4) uint8, (480, 640) float32
    >>> img.save("bunny.png")

Options are the command line's options as keyword arguments (``--no-shadows`` is
``no_shadows=True``, ``--light dir:0,-1,0 --light head`` is ``light=["dir:0,-1,0", "head"]``,
``--size 640x480`` is ``size=(640, 480)``, colours are tuples); they are checked by the same
parsers as the command line and a bad one raises :class:`OptionError` with its message.
"""
from __future__ import annotations

import json
import os
import threading
from typing import Any, Dict, List, Optional, Sequence, Tuple

import numpy as np

from ._glview import (
    BusyError,
    ContextError,
    GlviewError,
    ModelError,
    NativeRenderer,
    OptionError,
    __version__,
    encode_png,
    options_words,
)

__all__ = [
    "render",
    "Renderer",
    "Image",
    "diff",
    "GlviewError",
    "OptionError",
    "ModelError",
    "BusyError",
    "ContextError",
    "options_words",
    "__version__",
]

# Options of the Python API that are not command-line options: which buffers to read back.
_OUTPUTS = ("depth", "normals", "ids")


def _value(name: str, v: Any) -> Any:
    if isinstance(v, os.PathLike):
        return os.fspath(v)
    if isinstance(v, np.ndarray):
        return v.tolist()
    if isinstance(v, tuple):
        return list(v)
    return v


def _options_json(options: Dict[str, Any]) -> str:
    return json.dumps({k: _value(k, v) for k, v in options.items() if v is not None})


class Image:
    """One rendered picture: ``color`` (H×W×4 uint8, straight alpha: the pixels ``glview -o``
    writes), and where asked for ``depth`` (H×W float32 distance along the view axis, ``inf``
    where empty), ``normals`` (H×W×3 float32 eye-space unit normals facing the camera, zero
    where empty), ``object_ids``/``material_ids`` (H×W int32, −1 where empty; names in
    ``object_names``/``material_names``). Displays itself in notebooks."""

    def __init__(
        self,
        color: np.ndarray,
        text: Optional[List[Tuple[str, str]]] = None,
        depth: Optional[np.ndarray] = None,
        normals: Optional[np.ndarray] = None,
        object_ids: Optional[np.ndarray] = None,
        material_ids: Optional[np.ndarray] = None,
        object_names: Sequence[str] = (),
        material_names: Sequence[str] = (),
        stats: Optional[dict] = None,
    ) -> None:
        self.color = color
        self.text = list(text or [])
        self.depth = depth
        self.normals = normals
        self.object_ids = object_ids
        self.material_ids = material_ids
        self.object_names = list(object_names)
        self.material_names = list(material_names)
        self.stats = stats or {}

    @property
    def rgb(self) -> np.ndarray:
        """The colour without alpha (H×W×3 uint8, a view)."""
        return self.color[..., :3]

    @property
    def width(self) -> int:
        return int(self.color.shape[1])

    @property
    def height(self) -> int:
        return int(self.color.shape[0])

    def png(self) -> bytes:
        """The PNG file's bytes, with glview's text chunks (the reproducing command line)."""
        c = np.ascontiguousarray(self.color, dtype=np.uint8)
        if c.ndim != 3 or c.shape[2] != 4:
            raise ValueError("color must be H×W×4 uint8")
        return encode_png(c.reshape(-1), c.shape[1], c.shape[0], self.text)

    def _repr_png_(self) -> bytes:
        return self.png()

    def save(self, path: "str | os.PathLike[str]") -> None:
        """Writes the picture as PNG (text chunks included)."""
        with open(path, "wb") as f:
            f.write(self.png())

    def __repr__(self) -> str:
        extra = [n for n in ("depth", "normals", "object_ids") if getattr(self, n) is not None]
        return f"<glview.Image {self.width}x{self.height}{' +' + ','.join(extra) if extra else ''}>"


def _model_arrays(model: Any) -> Optional[Dict[str, Optional[np.ndarray]]]:
    """Arrays of a model given as a dict, a (vertices, faces) pair or an object with
    ``.vertices``/``.faces`` (trimesh); None for a path."""
    if isinstance(model, (str, os.PathLike)):
        return None
    if isinstance(model, dict):
        get = model.get
    elif isinstance(model, (tuple, list)) and len(model) == 2:
        v, f = model
        get = {"vertices": v, "faces": f}.get
    elif hasattr(model, "vertices") and hasattr(model, "faces"):
        def get(name: str) -> Any:
            return getattr(model, name, None) if name in ("vertices", "faces") else None
    else:
        raise TypeError(
            "model must be a path, (vertices, faces), a dict of arrays or an object with "
            f".vertices and .faces, not {type(model).__name__}"
        )

    def arr(name: str, dtype: Any, width: int) -> Optional[np.ndarray]:
        a = get(name)
        if a is None:
            return None
        a = np.asarray(a, dtype=dtype)
        if a.ndim != 2 or a.shape[1] != width:
            raise ModelError(f"<arrays>: {name} must be N×{width}, not {a.shape}")
        return np.ascontiguousarray(a).reshape(-1)

    out = {
        "vertices": arr("vertices", np.float64, 3),
        "faces": arr("faces", np.int64, 3),
        "normals": arr("normals", np.float32, 3),
        "uvs": arr("uvs", np.float32, 2),
        "colors": arr("colors", np.float32, 3),
    }
    if out["vertices"] is None or out["faces"] is None:
        raise ModelError("<arrays>: vertices and faces are both needed")
    return out


class Renderer:
    """One kept OpenGL context for many pictures (as ``glview batch`` keeps it): the model is
    uploaded once, and the compiled shaders, environment maps and shadow maps are reused.

        with glview.Renderer(640, 480) as r:
            r.load("bunny.obj")
            pictures = [r.render(yaw=y) for y in range(0, 360, 15)]

    Options given here are the defaults of every :meth:`render`. A renderer draws one picture
    at a time: a call from a second thread while it draws raises :class:`BusyError`."""

    def __init__(self, width: int = 1024, height: int = 768, **options: Any) -> None:
        self._defaults = dict(options)
        self._defaults["size"] = (int(width), int(height))
        self._native: Optional[NativeRenderer] = NativeRenderer(self._options({}))
        self._names: Tuple[List[str], List[str]] = ([], [])
        self._lock = threading.Lock()

    def _options(self, options: Dict[str, Any]) -> str:
        merged = dict(self._defaults)
        merged.update(options)
        for k in _OUTPUTS:
            merged.pop(k, None)
        return _options_json(merged)

    def _get(self) -> NativeRenderer:
        if self._native is None:
            raise GlviewError("the renderer is closed")
        return self._native

    def load(self, model: Any, **options: Any) -> "Renderer":
        """Loads a model: a path (every format glview reads), arrays ``(vertices, faces)``,
        a dict with ``vertices``, ``faces`` and optional ``normals``, ``uvs``, ``colors``, or
        an object with ``.vertices``/``.faces`` such as a ``trimesh.Trimesh``. Loading options
        (``up``, ``crease``, ``flat``, ``texture``, ...) are keyword arguments."""
        opts = self._options(options)
        arrays = _model_arrays(model)
        native = self._get()
        if arrays is None:
            self._names = native.load_path(os.fspath(model), opts)
            # The PNG text's reproducing command line names the file.
            self._defaults["model"] = os.fspath(model)
        else:
            self._defaults.pop("model", None)
            self._names = native.load_arrays(
                arrays["vertices"], arrays["faces"], arrays["normals"], arrays["uvs"],
                arrays["colors"], opts,
            )
        return self

    def render(
        self, *, depth: bool = False, normals: bool = False, ids: bool = False, **options: Any
    ) -> Image:
        """Renders the loaded model (else the ``model`` option, else the built-in scene) with
        these options over the renderer's; ``depth``/``normals``/``ids`` read those buffers
        back too."""
        native = self._get()
        out = native.render(self._options(options), depth, normals, ids)
        return Image(
            out["color"],
            out["text"],
            depth=out.get("depth") if depth else None,
            normals=out.get("normals") if normals else None,
            object_ids=out.get("object_ids") if ids else None,
            material_ids=out.get("material_ids") if ids else None,
            object_names=self._names[0],
            material_names=self._names[1],
            stats=json.loads(out["stats"]),
        )

    def close(self) -> None:
        """Releases the context and everything uploaded (also done on ``with`` exit)."""
        if self._native is not None:
            self._native.close()
            self._native = None

    def __enter__(self) -> "Renderer":
        return self

    def __exit__(self, *exc: Any) -> None:
        self.close()

    def __del__(self) -> None:
        try:
            self.close()
        except Exception:
            pass


def render(
    model: Any = None,
    *,
    depth: bool = False,
    normals: bool = False,
    ids: bool = False,
    **options: Any,
) -> Image:
    """Renders one picture of ``model`` (a path, arrays, or an object with ``.vertices`` and
    ``.faces``; None: the built-in scene) with the command line's options as keyword
    arguments, e.g. ``render("bunny.obj", size=(640, 480), shading="pbr", no_shadows=True)``.
    """
    size = options.pop("size", (1024, 768))
    with Renderer(size[0], size[1]) as r:
        if model is not None:
            r.load(model, **options)
        return r.render(depth=depth, normals=normals, ids=ids, **options)


def diff(a: "Image | np.ndarray", b: "Image | np.ndarray") -> Tuple[Image, Dict[str, float]]:
    """The difference of two pictures as ``glview --diff`` measures it: an image of the
    per-pixel maximum channel difference (grey, amplified ×4) and a dict with ``mean`` (in
    1/255), ``max``, ``p99`` and ``share_over_8`` (share of pixels differing by more than
    8/255)."""
    ca = (a.color if isinstance(a, Image) else np.asarray(a))[..., :3].astype(np.int16)
    cb = (b.color if isinstance(b, Image) else np.asarray(b))[..., :3].astype(np.int16)
    if ca.shape != cb.shape:
        raise ValueError(f"pictures differ in size: {ca.shape[:2]} and {cb.shape[:2]}")
    d = np.abs(ca - cb)
    per_pixel = d.max(axis=2)
    numbers = {
        "mean": float(d.mean()),
        "max": float(per_pixel.max()),
        "p99": float(np.percentile(per_pixel, 99)),
        "share_over_8": float((per_pixel > 8).mean()),
    }
    grey = np.clip(per_pixel.astype(np.int32) * 4, 0, 255).astype(np.uint8)
    img = np.dstack([grey, grey, grey, np.full_like(grey, 255)])
    return Image(np.ascontiguousarray(img)), numbers
