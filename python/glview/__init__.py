"""glview from Python: render models to NumPy arrays.

    >>> import glview
    >>> img = glview.render("bunny.obj", size=(640, 480), yaw=30, depth=True)
    >>> img.color.shape, img.depth.shape      # (480, 640, 4) uint8, (480, 640) float32
    >>> img.save("bunny.png")

Options are the command line's options as keyword arguments (``--no-shadows`` is
``no_shadows=True``, ``--light dir:0,-1,0 --light head`` is ``light=["dir:0,-1,0", "head"]``,
``--size 640x480`` is ``size=(640, 480)``, colours are tuples); they are checked by the same
specs as the command line (the list: docs/options.md) and a bad one raises
:class:`OptionError` naming the keyword and the value (``yaw: expected a number, got 'north'``).
"""
from __future__ import annotations

import atexit
import json
import os
import threading
from typing import Any, Callable, Dict, List, Optional, Sequence, Tuple

import numpy as np

from . import _glview as _native

# A large model's first load writes its mesh cache entry on another thread while the first
# picture is drawn: let it finish before the process ends.
atexit.register(_native.wait_for_cache_writes)
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
    "release",
    "Renderer",
    "Image",
    "diff",
    "diff_tiers",
    "compare",
    "sheet",
    "export",
    "GlviewError",
    "OptionError",
    "ModelError",
    "BusyError",
    "ContextError",
    "options_words",
    "__version__",
]

# Options of the Python API that are not command-line options: which buffers to read back.
_OUTPUTS = ("depth", "normals", "ids", "linear")


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
    ``object_names``/``material_names``), ``linear`` (H×W×3 float32: the colour before bloom,
    exposure, tone mapping and sRGB, unclamped; a second frame). Displays itself in
    notebooks."""

    def __init__(
        self,
        color: np.ndarray,
        text: Optional[List[Tuple[str, str]]] = None,
        depth: Optional[np.ndarray] = None,
        normals: Optional[np.ndarray] = None,
        object_ids: Optional[np.ndarray] = None,
        material_ids: Optional[np.ndarray] = None,
        linear: Optional[np.ndarray] = None,
        object_names: Sequence[str] = (),
        material_names: Sequence[str] = (),
        stats: Optional[dict] = None,
    ) -> None:
        self.color = color
        # A native PictureText is made into pairs on first use of ``text`` (a picture used
        # as arrays never pays for its options' JSON and command line).
        self._text: Any = text if isinstance(text, _native.PictureText) else list(text or [])
        self.depth = depth
        self.normals = normals
        self.object_ids = object_ids
        self.material_ids = material_ids
        self.linear = linear
        self.object_names = list(object_names)
        self.material_names = list(material_names)
        self.stats = stats or {}

    @property
    def text(self) -> List[Tuple[str, str]]:
        """The PNG text chunks (renderer, camera, the reproducing command line) as pairs."""
        if isinstance(self._text, _native.PictureText):
            self._text = self._text.pairs()
        return self._text

    @text.setter
    def text(self, text: List[Tuple[str, str]]) -> None:
        self._text = list(text)

    def __getstate__(self) -> Dict[str, Any]:
        # Pickled (a dask result) with its text as pairs: the native object does not pickle.
        state = dict(self.__dict__)
        state["_text"] = self.text
        return state

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

    A glTF animation plays the same way: ``[r.render(time=k / 15) for k in range(45)]`` (and
    ``animation=`` by index or name) loads and uploads the model once, and each moment uploads
    again only the meshes its pose moved.

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
        self,
        *,
        depth: bool = False,
        normals: bool = False,
        ids: bool = False,
        linear: bool = False,
        eyes: bool = False,
        **options: Any,
    ) -> Any:
        """Renders the loaded model (else the ``model`` option, else the built-in scene) with
        these options over the renderer's; ``depth``/``normals``/``ids`` read those buffers
        back too. ``eyes=True`` returns the stereo pair instead, ``(left, right)``: each the
        ``eye=`` picture of the ``stereo=`` mode (at its size there), sharing the upload,
        shadow and environment maps."""
        if eyes:
            if options.get("eye") is not None:
                raise OptionError("eyes: draws both eyes; it cannot be used with eye=")
            one = dict(depth=depth, normals=normals, ids=ids, linear=linear)
            return tuple(self.render(**one, eye=e, **options) for e in ("left", "right"))
        native = self._get()
        out = native.render(self._options(options), depth, normals, ids, linear)
        return Image(
            out["color"],
            out["text"],
            depth=out.get("depth") if depth else None,
            normals=out.get("normals") if normals else None,
            object_ids=out.get("object_ids") if ids else None,
            material_ids=out.get("material_ids") if ids else None,
            linear=out.get("linear"),
            object_names=self._names[0],
            material_names=self._names[1],
            stats=json.loads(out["stats"]),
        )

    def hold(self, callback: Callable[[], Any]) -> None:
        """Calls ``callback`` while this thread holds the renderer: another thread's
        ``render`` meanwhile raises :class:`BusyError`, as it does while a picture is drawn."""
        self._get().hold(callback)

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


# The renderer that render() calls share: made by the first, kept until release(). A new
# context per call cost 40-50 ms and compiled every shader again.
_shared: Optional[Renderer] = None
_shared_lock = threading.Lock()


def render(
    model: Any = None,
    *,
    depth: bool = False,
    normals: bool = False,
    ids: bool = False,
    linear: bool = False,
    eyes: bool = False,
    **options: Any,
) -> Any:
    """Renders one picture of ``model`` (a path, arrays, or an object with ``.vertices`` and
    ``.faces``; None: the built-in scene) with the command line's options as keyword
    arguments, e.g. ``render("bunny.obj", size=(640, 480), shading="pbr", no_shadows=True)``.

    Calls share one OpenGL context, made by the first and kept until :func:`release`, so a
    picture costs what it costs on a kept :class:`Renderer` plus loading its model. A call
    made while another thread's call draws does not wait: it renders in a temporary context
    of its own, closed when it returns.
    """
    global _shared
    size = options.pop("size", (1024, 768))
    outputs = dict(depth=depth, normals=normals, ids=ids, linear=linear, eyes=eyes)
    if not _shared_lock.acquire(blocking=False):
        with Renderer(size[0], size[1]) as r:
            return _render_in(r, model, size, outputs, options)
    try:
        if _shared is None:
            _shared = Renderer(size[0], size[1])
        return _render_in(_shared, model, size, outputs, options)
    finally:
        _shared_lock.release()


def _render_in(
    r: Renderer, model: Any, size: Any, outputs: Dict[str, bool], options: Dict[str, Any]
) -> Any:
    """One picture of render() in ``r``, which forgets the last call's model and size."""
    r._defaults = {"size": (int(size[0]), int(size[1]))}
    r._names = ([], [])
    if model is None:
        r._get().unload()
    else:
        r.load(model, **options)
    return r.render(**outputs, **options)


def release() -> None:
    """Closes the context that :func:`render` calls share, releasing its memory (the next
    call makes a new one); waits for a call drawing in it. Without it, it is kept until the
    process ends."""
    global _shared
    with _shared_lock:
        if _shared is not None:
            _shared.close()
            _shared = None


def _numbers(n: Dict[str, float]) -> Dict[str, float]:
    """The command line's numbers under the Python API's names."""
    return {
        "mean": n["mean"],
        "max": n["max"],
        "p99": n["p99"],
        "share_over_8": n["over_8"],
        "ssim": 1.0 - n["one_minus_ssim"],
        "one_minus_ssim": n["one_minus_ssim"],
    }


def _rgba(x: "Image | np.ndarray") -> np.ndarray:
    c = np.asarray(x.color if isinstance(x, Image) else x)
    if c.ndim != 3 or c.shape[2] not in (3, 4):
        raise ValueError(f"a picture is H×W×3 or H×W×4, not {c.shape}")
    if c.shape[2] == 3:
        c = np.dstack([c, np.full(c.shape[:2], 255, c.dtype)])
    return np.ascontiguousarray(c, dtype=np.uint8)


def _coverage(x: "Image | np.ndarray") -> Optional[np.ndarray]:
    """Where a picture shows the model: its object ids where it has them, else its alpha
    when it was rendered with a transparent background; None when it does not say."""
    if isinstance(x, Image) and x.object_ids is not None:
        return x.object_ids >= 0
    c = _rgba(x)
    return c[..., 3] > 0 if (c[..., 3] < 255).any() else None


def diff(a: "Image | np.ndarray", b: "Image | np.ndarray") -> Tuple[Image, Dict[str, Any]]:
    """Two pictures compared as ``glview --diff`` compares them (the same code): the
    difference image (|a − b|, largest channel, on a colour scale with its range written
    under it, so it is taller than the pictures) and a dict with ``mean`` (in 1/255),
    ``max``, ``p99``, ``share_over_8`` (share of pixels more than 8/255 apart), ``ssim`` and
    ``one_minus_ssim``. Where the pictures say which pixels are the model's (``ids=True``,
    or ``transparent=True``), ``model`` holds the same numbers over the union of those
    pixels and ``model_pixels`` their count, and the difference image shows only those
    pixels (0 elsewhere); else ``model`` is None."""
    ca, cb = _rgba(a), _rgba(b)
    if ca.shape != cb.shape:
        raise ValueError(f"pictures differ in size: {ca.shape[:2]} and {cb.shape[:2]}")
    cov_a, cov_b = _coverage(a), _coverage(b)
    covered = None
    if cov_a is not None or cov_b is not None:
        covered = np.zeros(ca.shape[:2], bool)
        for c in (cov_a, cov_b):
            if c is not None:
                covered |= c
        covered = np.ascontiguousarray(covered).reshape(-1)
    img, numbers = _native.diff_images(
        ca.reshape(-1), cb.reshape(-1), ca.shape[1], ca.shape[0], covered
    )
    n = json.loads(numbers)
    out: Dict[str, Any] = _numbers(n["numbers"])
    out["model"] = _numbers(n["model"]) if n["model"] else None
    out["model_pixels"] = n["model_pixels"]
    return Image(img), out


def _path_options(model: Any, options: Dict[str, Any]) -> str:
    if model is not None and not isinstance(model, (str, os.PathLike)):
        raise TypeError(
            "compare, diff_tiers, sheet and export take a model file (or None for the built-in "
            f"scene), not {type(model).__name__}"
        )
    if model is not None:
        options = {**options, "model": os.fspath(model)}
    return _options_json(options)


def compare(model: Any = None, tiers: str = "phong,pbr", **options: Any) -> Image:
    """``glview MODEL --compare TIERS``: the tiers side by side on one camera under one
    label strip (tiers: phong, gouraud, pbr, reference, reference-pbr); ``size`` is each
    pane's."""
    img, text = _native.compare(_path_options(model, options), tiers)
    return Image(img, text)


def diff_tiers(
    model: Any = None, tiers: str = "phong,pbr", **options: Any
) -> Tuple[Image, Dict[str, Any]]:
    """``glview MODEL --diff A,B``: two tiers rendered on one camera and compared. Returns
    the difference image and the numbers as :func:`diff` names them, over the whole picture
    and (``model``) over the model's pixels (the union of both tiers' coverage), plus the
    two pictures (``a``, ``b``: Images) and the tiers' names (``names``)."""
    img, a, b, numbers = _native.diff_tiers(_path_options(model, options), tiers)
    n = json.loads(numbers)
    out: Dict[str, Any] = _numbers(n["numbers"])
    out["model"] = _numbers(n["model"]) if n["model"] else None
    out["model_pixels"] = n["model_pixels"]
    out["names"] = (n["a"], n["b"])
    out["a"], out["b"] = Image(a), Image(b)
    return Image(img), out


def export(
    model: Any,
    path: "str | os.PathLike[str]",
    yaw_steps: int = 36,
    pitch_steps: int = 5,
    pitch_step: float = 15.0,
    quality: int = 85,
    png: bool = False,
    title: Optional[str] = None,
    caption: Optional[str] = None,
    max_size: Optional[int] = None,
    scorm: "str | os.PathLike[str] | None" = None,
    live: "bool | str" = False,
    web_dir: "str | os.PathLike[str] | None" = None,
    **options: Any,
) -> Dict[str, Any]:
    """``glview export MODEL -o PATH``: the lesson page (one self-contained HTML file of
    turntable views, Phong and PBR, docs/export.md) and with ``scorm`` its SCORM 1.2
    package. ``live=True`` (``--live``) also carries glview's renderer, which draws the
    model live where the browser can; ``live="only"`` leaves the pictures out; ``web_dir``
    names the browser build (docs/web.md). ``size`` is each picture's (default 640×480);
    the other keywords are the picture's options. Returns what the page cost: views, bytes,
    picture_bytes, title."""
    options = {"size": (640, 480), **options}
    own = {
        "yaw_steps": yaw_steps,
        "pitch_steps": pitch_steps,
        "pitch_step": pitch_step,
        "quality": quality,
        "png": png,
        "title": title,
        "caption": caption,
        "max_size": max_size,
        "scorm": None if scorm is None else os.fspath(scorm),
        "live": live,
        "web_dir": None if web_dir is None else os.fspath(web_dir),
    }
    out = _native.export(_path_options(model, options), os.fspath(path), json.dumps(own))
    return json.loads(out)


def sheet(
    model: Any = None,
    tiers: str = "phong,pbr",
    views: int = 6,
    angles: Optional[str] = None,
    **options: Any,
) -> Image:
    """``glview sheet MODEL``: a labelled grid of turntable views (columns) by tiers (rows);
    ``angles="0:20,90:20"`` gives the views explicitly; ``size`` is each cell's."""
    return Image(_native.sheet(_path_options(model, options), tiers, views, angles))
