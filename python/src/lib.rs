//! `glview._glview`: the native half of the Python package. It holds no rendering of its
//! own: options go to `glview::Options` (keyword names and JSON values, through the option
//! specs the command line is made from), models to `glview::api::Model`, pictures come from
//! `glview::api::Renderer`. Buffers move into NumPy arrays without a copy.
use glview::api::{self, Arrays, Model, Outputs};
use glview::image_out::Rgba;
use glview::image_out::RgbaFiles;
use glview::{Error, Options};
use numpy::{IntoPyArray, PyArrayMethods, PyReadonlyArray1};
use pyo3::create_exception;
use pyo3::exceptions::PyException;
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyDict};
use std::path::PathBuf;

create_exception!(_glview, GlviewError, PyException, "Any error of glview.");
create_exception!(
    _glview,
    OptionError,
    GlviewError,
    "A bad option: the command line's message."
);
create_exception!(
    _glview,
    ModelError,
    GlviewError,
    "A model file or array that cannot be used."
);
create_exception!(
    _glview,
    BusyError,
    GlviewError,
    "A renderer called from a second thread while it draws for the first."
);
create_exception!(
    _glview,
    ContextError,
    GlviewError,
    "No OpenGL context could be made."
);

fn py_err(e: Error) -> PyErr {
    let msg = e.to_string();
    match e {
        Error::Usage(_) => OptionError::new_err(msg),
        Error::Model { .. } | Error::Io { .. } | Error::Image { .. } => ModelError::new_err(msg),
        Error::Busy => BusyError::new_err(msg),
        Error::Context(_) | Error::Osmesa(_) => ContextError::new_err(msg),
        _ => GlviewError::new_err(msg),
    }
}

/// Keyword arguments (a JSON object of names and values) straight into `Options`; an error
/// names the keyword: `yaw: expected a number, got 'north'`.
fn options(json: &str) -> PyResult<Options> {
    let map: serde_json::Map<String, serde_json::Value> =
        serde_json::from_str(json).map_err(|e| OptionError::new_err(e.to_string()))?;
    Options::from_keywords(map.iter().map(|(k, v)| (k.as_str(), v)))
        .map_err(|e| OptionError::new_err(e.as_keyword()))
}

/// Options as the command line's words after the model (`options_words('{"yaw": 5}')`).
#[pyfunction]
fn options_words(json: &str) -> PyResult<Vec<String>> {
    Ok(options(json)?.to_words())
}

/// A picture's PNG text, made when `pairs()` is called (`glview.Image.text` calls it on
/// first use): a picture used only as arrays never serialises its options.
#[pyclass(module = "glview._glview", frozen)]
struct PictureText(glview::session::PictureText);

#[pymethods]
impl PictureText {
    fn pairs(&self) -> Vec<(String, String)> {
        self.0
            .text()
            .into_iter()
            .map(|(k, v)| (k.to_string(), v))
            .collect()
    }
}

/// A kept OpenGL context on a thread of its own (see `glview.Renderer`).
#[pyclass(module = "glview._glview")]
struct NativeRenderer {
    inner: Option<api::Renderer>,
}

impl NativeRenderer {
    fn get(&mut self) -> PyResult<&mut api::Renderer> {
        self.inner
            .as_mut()
            .ok_or_else(|| GlviewError::new_err("the renderer is closed"))
    }
}

#[pymethods]
impl NativeRenderer {
    #[new]
    fn new(py: Python<'_>, options_json: &str) -> PyResult<Self> {
        let o = options(options_json)?;
        let r = py.detach(move || api::Renderer::new(o)).map_err(py_err)?;
        Ok(NativeRenderer { inner: Some(r) })
    }

    /// Loads a model file; returns (object names, material names).
    fn load_path(
        &mut self,
        py: Python<'_>,
        path: std::path::PathBuf,
        options_json: &str,
    ) -> PyResult<(Vec<String>, Vec<String>)> {
        let o = options(options_json)?;
        let m = py.detach(|| Model::load(&path, &o)).map_err(py_err)?;
        let names = (m.object_names(), m.material_names());
        self.get()?.load(m);
        Ok(names)
    }

    /// Loads arrays (flat, C order): vertices f64, faces i64, optional normals, uvs, colours.
    #[pyo3(signature = (vertices, faces, normals, uvs, colors, options_json))]
    #[allow(clippy::too_many_arguments)]
    fn load_arrays(
        &mut self,
        py: Python<'_>,
        vertices: PyReadonlyArray1<f64>,
        faces: PyReadonlyArray1<i64>,
        normals: Option<PyReadonlyArray1<f32>>,
        uvs: Option<PyReadonlyArray1<f32>>,
        colors: Option<PyReadonlyArray1<f32>>,
        options_json: &str,
    ) -> PyResult<(Vec<String>, Vec<String>)> {
        let o = options(options_json)?;
        let slice = |a: &PyReadonlyArray1<f32>| a.as_slice().map(<[f32]>::to_vec);
        let contiguous = |e| GlviewError::new_err(format!("arrays must be contiguous: {e}"));
        let a = (
            vertices.as_slice().map_err(contiguous)?.to_vec(),
            faces.as_slice().map_err(contiguous)?.to_vec(),
            normals
                .as_ref()
                .map(slice)
                .transpose()
                .map_err(contiguous)?,
            uvs.as_ref().map(slice).transpose().map_err(contiguous)?,
            colors.as_ref().map(slice).transpose().map_err(contiguous)?,
        );
        let m = py
            .detach(|| {
                let arrays = Arrays {
                    vertices: &a.0,
                    faces: &a.1,
                    normals: a.2.as_deref(),
                    uvs: a.3.as_deref(),
                    colors: a.4.as_deref(),
                };
                Model::from_arrays(&arrays, &o)
            })
            .map_err(py_err)?;
        let names = (m.object_names(), m.material_names());
        self.get()?.load(m);
        Ok(names)
    }

    /// Draws the `model` option's file (or the built-in scene) again instead of the loaded
    /// model (`glview.render` reuses one renderer for many models).
    fn unload(&mut self) -> PyResult<()> {
        self.get()?.unload();
        Ok(())
    }

    /// Renders a job of `glview batch`: the words of its line without `--output`; returns
    /// the PNG file's bytes, the same bytes `glview batch` writes for that line.
    fn render_words<'py>(
        &self,
        py: Python<'py>,
        words: Vec<String>,
    ) -> PyResult<Bound<'py, PyBytes>> {
        let o =
            Options::from_words(words).map_err(|e| OptionError::new_err(e.on_command_line()))?;
        let r = self
            .inner
            .as_ref()
            .ok_or_else(|| GlviewError::new_err("the renderer is closed"))?;
        let png = py
            .detach(|| r.render(&o, Outputs::default()).map(|f| f.png()))
            .map_err(py_err)?;
        Ok(PyBytes::new(py, &png))
    }

    /// Renders; returns a dict of NumPy arrays (color, and as asked depth, normals,
    /// object_ids and material_ids) and the PNG text (a `PictureText`: its pairs made when
    /// asked for).
    fn render<'py>(
        &self,
        py: Python<'py>,
        options_json: &str,
        depth: bool,
        normals: bool,
        ids: bool,
        linear: bool,
    ) -> PyResult<Bound<'py, PyDict>> {
        let o = options(options_json)?;
        let r = self
            .inner
            .as_ref()
            .ok_or_else(|| GlviewError::new_err("the renderer is closed"))?;
        let frame = py
            .detach(|| {
                let outputs = Outputs {
                    depth,
                    normals,
                    ids,
                    linear,
                };
                r.render(&o, outputs)
            })
            .map_err(py_err)?;
        let out = PyDict::new(py);
        let (w, h) = (frame.color.width as usize, frame.color.height as usize);
        let color = frame.color.data.into_pyarray(py).reshape([h, w, 4])?;
        out.set_item("color", color)?;
        out.set_item("text", Bound::new(py, PictureText(frame.repro))?)?;
        out.set_item("stats", frame.stats.to_string())?;
        if let Some(l) = frame.linear {
            let l: Vec<f32> = l.into_iter().flatten().collect();
            out.set_item("linear", l.into_pyarray(py).reshape([h, w, 3])?)?;
        }
        if let Some(a) = frame.attributes {
            if depth {
                out.set_item("depth", a.depth.into_pyarray(py).reshape([h, w])?)?;
            }
            if normals {
                let n: Vec<f32> = a.normals.into_iter().flatten().collect();
                out.set_item("normals", n.into_pyarray(py).reshape([h, w, 3])?)?;
            }
            if ids {
                out.set_item("object_ids", a.object_ids.into_pyarray(py).reshape([h, w])?)?;
                out.set_item(
                    "material_ids",
                    a.material_ids.into_pyarray(py).reshape([h, w])?,
                )?;
            }
        }
        Ok(out)
    }

    /// Calls `callback` while holding the renderer (other threads get BusyError meanwhile).
    fn hold(&self, py: Python<'_>, callback: Py<PyAny>) -> PyResult<()> {
        let r = self
            .inner
            .as_ref()
            .ok_or_else(|| GlviewError::new_err("the renderer is closed"))?;
        let _held = r.reserve().map_err(py_err)?;
        callback.call0(py)?;
        Ok(())
    }

    /// Ends the renderer's thread and releases its context.
    fn close(&mut self, py: Python<'_>) {
        if let Some(mut r) = self.inner.take() {
            py.detach(move || r.close());
        }
    }
}

/// PNG bytes of an RGBA8 picture (height × width × 4, C order) with text chunks.
#[pyfunction]
fn encode_png<'py>(
    py: Python<'py>,
    rgba: PyReadonlyArray1<u8>,
    width: u32,
    height: u32,
    text: Vec<(String, String)>,
) -> PyResult<Bound<'py, PyBytes>> {
    let data = rgba
        .as_slice()
        .map_err(|e| GlviewError::new_err(e.to_string()))?
        .to_vec();
    if data.len() != (width * height * 4) as usize {
        return Err(GlviewError::new_err("pixel buffer size mismatch"));
    }
    let img = glview::image_out::Rgba {
        width,
        height,
        data,
    };
    let text: Vec<(&str, String)> = text.iter().map(|(k, v)| (k.as_str(), v.clone())).collect();
    Ok(PyBytes::new(py, &img.png_bytes(&text)))
}

/// An RGBA8 NumPy array (height × width × 4) of a PNG file.
#[pyfunction]
fn decode_png<'py>(
    py: Python<'py>,
    path: std::path::PathBuf,
) -> PyResult<Bound<'py, numpy::PyArray3<u8>>> {
    let img = glview::image_out::Rgba::load_png(&path).map_err(py_err)?;
    let (w, h) = (img.width as usize, img.height as usize);
    img.data.into_pyarray(py).reshape([h, w, 4])
}

/// An RGBA8 picture from a flat buffer of `width * height * 4` bytes.
fn rgba(data: PyReadonlyArray1<u8>, width: u32, height: u32) -> PyResult<Rgba> {
    let data = data
        .as_slice()
        .map_err(|e| GlviewError::new_err(e.to_string()))?
        .to_vec();
    if data.len() != (width as usize) * (height as usize) * 4 {
        return Err(GlviewError::new_err("pixel buffer size mismatch"));
    }
    Ok(Rgba {
        width,
        height,
        data,
    })
}

/// An H×W×4 uint8 picture on the Python side.
type Picture<'py> = Bound<'py, numpy::PyArray3<u8>>;

fn array<'py>(py: Python<'py>, img: Rgba) -> PyResult<Picture<'py>> {
    let (w, h) = (img.width as usize, img.height as usize);
    img.data.into_pyarray(py).reshape([h, w, 4])
}

/// `--compare TIERS`: the panes under their labels and the PNG text.
#[pyfunction]
fn compare<'py>(
    py: Python<'py>,
    options_json: &str,
    tiers: &str,
) -> PyResult<(Picture<'py>, Vec<(String, String)>)> {
    let o = options(options_json)?;
    let tiers = tiers.to_string();
    let (img, text) = py
        .detach(move || glview::compare::compare_image(&o, &tiers))
        .map_err(py_err)?;
    let text = text.into_iter().map(|(k, v)| (k.to_string(), v)).collect();
    Ok((array(py, img)?, text))
}

/// `--diff A,B`: the difference image, both panes and the numbers as JSON.
#[pyfunction]
fn diff_tiers<'py>(
    py: Python<'py>,
    options_json: &str,
    tiers: &str,
) -> PyResult<(Picture<'py>, Picture<'py>, Picture<'py>, String)> {
    let o = options(options_json)?;
    let tiers = tiers.to_string();
    let d = py
        .detach(move || glview::compare::diff::diff_tiers(&o, &tiers))
        .map_err(py_err)?;
    let json = d.json().to_string();
    Ok((array(py, d.image)?, array(py, d.a)?, array(py, d.b)?, json))
}

/// Two pictures compared as `--diff` compares them; `covered` (one flag per pixel) adds the
/// numbers over those pixels. Returns the difference image and the numbers as JSON.
#[pyfunction]
#[pyo3(signature = (a, b, width, height, covered))]
fn diff_images<'py>(
    py: Python<'py>,
    a: PyReadonlyArray1<u8>,
    b: PyReadonlyArray1<u8>,
    width: u32,
    height: u32,
    covered: Option<PyReadonlyArray1<bool>>,
) -> PyResult<(Picture<'py>, String)> {
    let (a, b) = (rgba(a, width, height)?, rgba(b, width, height)?);
    let covered = covered
        .map(|c| c.as_slice().map(<[bool]>::to_vec))
        .transpose()
        .map_err(|e| GlviewError::new_err(e.to_string()))?;
    if covered
        .as_ref()
        .is_some_and(|c| c.len() != (width * height) as usize)
    {
        return Err(GlviewError::new_err("coverage size mismatch"));
    }
    let (img, numbers, model) =
        glview::compare::diff::diff_images(&a, &b, covered.as_deref()).map_err(py_err)?;
    let json = serde_json::json!({
        "numbers": numbers,
        "model": model,
        "model_pixels": covered.map(|c| c.iter().filter(|&&x| x).count()),
    });
    Ok((array(py, img)?, json.to_string()))
}

/// `glview sheet`: the labelled grid of views by tiers.
#[pyfunction]
#[pyo3(signature = (options_json, tiers, views, angles))]
fn sheet<'py>(
    py: Python<'py>,
    options_json: &str,
    tiers: &str,
    views: u32,
    angles: Option<String>,
) -> PyResult<Picture<'py>> {
    let o = options(options_json)?;
    let cmd = glview::compare::sheet::Sheet {
        size: o.picture.size,
        options: o,
        views,
        angles,
        tiers: tiers.to_string(),
    };
    let (img, _, _) = py
        .detach(move || glview::compare::sheet::sheet_image(&cmd))
        .map_err(py_err)?;
    array(py, img)
}

/// `glview export`: the lesson page of the picture options and the export's own (a JSON
/// object) written to `path` (and the SCORM package where asked); its summary as JSON.
#[pyfunction]
fn export(
    py: Python<'_>,
    options_json: &str,
    path: PathBuf,
    export_json: &str,
) -> PyResult<String> {
    let o = options(options_json)?;
    let keywords: serde_json::Value = serde_json::from_str(export_json)
        .map_err(|e| pyo3::exceptions::PyValueError::new_err(e.to_string()))?;
    let opts = glview::export::ExportOptions::with_keywords(o, &keywords).map_err(py_err)?;
    let e = py
        .detach(move || glview::export::write(&opts, &path))
        .map_err(py_err)?;
    Ok(serde_json::json!({
        "views": e.views,
        "bytes": e.html.len(),
        "picture_bytes": e.picture_bytes,
        "title": e.title,
        "summary": e.summary,
    })
    .to_string())
}

/// Waits until the mesh cache entries being written on other threads (a large model's
/// levels of detail, built while its first picture was drawn) are written; the package
/// calls it at exit, so a short script's first load still leaves its entry.
#[pyfunction]
fn wait_for_cache_writes(py: Python<'_>) {
    py.detach(glview::scene::cache::wait_for_writes);
}

#[pymodule]
fn _glview(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add_class::<NativeRenderer>()?;
    m.add_class::<PictureText>()?;
    m.add_function(wrap_pyfunction!(encode_png, m)?)?;
    m.add_function(wrap_pyfunction!(options_words, m)?)?;
    m.add_function(wrap_pyfunction!(decode_png, m)?)?;
    m.add_function(wrap_pyfunction!(compare, m)?)?;
    m.add_function(wrap_pyfunction!(diff_tiers, m)?)?;
    m.add_function(wrap_pyfunction!(diff_images, m)?)?;
    m.add_function(wrap_pyfunction!(sheet, m)?)?;
    m.add_function(wrap_pyfunction!(export, m)?)?;
    m.add_function(wrap_pyfunction!(wait_for_cache_writes, m)?)?;
    m.add("GlviewError", py.get_type::<GlviewError>())?;
    m.add("OptionError", py.get_type::<OptionError>())?;
    m.add("ModelError", py.get_type::<ModelError>())?;
    m.add("BusyError", py.get_type::<BusyError>())?;
    m.add("ContextError", py.get_type::<ContextError>())?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
