//! Posing tests (no GL) on generated files: a skin whose nodes pose it away from its bind
//! pose, morph weights from the mesh, the node and an animation, the framing bounds, and
//! hostile files (each a warning naming the problem, never a panic, bounded memory).
use crate::load::load_bytes;
use crate::motion::Moment;
use glam::Vec3;
use std::path::Path;
use {crate::load::options::LoadOptions, crate::model::Scene};

/// A GLB under construction: one binary buffer, views and accessors appended.
#[derive(Default)]
pub(crate) struct Glb {
    bin: Vec<u8>,
    views: Vec<String>,
    accessors: Vec<String>,
}

impl Glb {
    fn view(&mut self, bytes: &[u8]) -> usize {
        while !self.bin.len().is_multiple_of(4) {
            self.bin.push(0);
        }
        self.views.push(format!(
            r#"{{"buffer":0,"byteOffset":{},"byteLength":{}}}"#,
            self.bin.len(),
            bytes.len()
        ));
        self.bin.extend_from_slice(bytes);
        self.views.len() - 1
    }

    /// A float accessor of `kind` (SCALAR, VEC3, VEC4, MAT4); `count` may claim more
    /// elements than the data holds (a hostile file).
    pub(crate) fn floats(&mut self, data: &[f32], kind: &str, count: usize) -> usize {
        let bytes: Vec<u8> = data.iter().flat_map(|f| f.to_le_bytes()).collect();
        let v = self.view(&bytes);
        let minmax = if kind == "VEC3" && data.iter().all(|x| x.is_finite()) {
            let col = |c: usize, f: fn(f32, f32) -> f32| {
                data.iter().skip(c).step_by(3).copied().fold(data[c], f)
            };
            format!(
                r#","min":[{},{},{}],"max":[{},{},{}]"#,
                col(0, f32::min),
                col(1, f32::min),
                col(2, f32::min),
                col(0, f32::max),
                col(1, f32::max),
                col(2, f32::max)
            )
        } else {
            String::new()
        };
        self.accessors.push(format!(
            r#"{{"bufferView":{v},"componentType":5126,"count":{count},"type":"{kind}"{minmax}}}"#
        ));
        self.accessors.len() - 1
    }

    pub(crate) fn u16s(&mut self, data: &[u16], kind: &str) -> usize {
        let bytes: Vec<u8> = data.iter().flat_map(|f| f.to_le_bytes()).collect();
        let v = self.view(&bytes);
        let per = if kind == "VEC4" { 4 } else { 1 };
        self.accessors.push(format!(
            r#"{{"bufferView":{v},"componentType":5123,"count":{},"type":"{kind}"}}"#,
            data.len() / per
        ));
        self.accessors.len() - 1
    }

    /// The GLB of `rest` (the JSON's other members, without braces) and the data.
    pub(crate) fn bytes(&self, rest: &str) -> Vec<u8> {
        let mut bin = self.bin.clone();
        while !bin.len().is_multiple_of(4) {
            bin.push(0);
        }
        let mut json = format!(
            r#"{{"asset":{{"version":"2.0"}},"buffers":[{{"byteLength":{}}}],"bufferViews":[{}],"accessors":[{}],{rest}}}"#,
            bin.len(),
            self.views.join(","),
            self.accessors.join(",")
        )
        .into_bytes();
        while !json.len().is_multiple_of(4) {
            json.push(b' ');
        }
        let total = 12 + 8 + json.len() + 8 + bin.len();
        let mut out = Vec::new();
        out.extend_from_slice(b"glTF");
        out.extend_from_slice(&2u32.to_le_bytes());
        out.extend_from_slice(&(total as u32).to_le_bytes());
        out.extend_from_slice(&(json.len() as u32).to_le_bytes());
        out.extend_from_slice(b"JSON");
        out.extend_from_slice(&json);
        out.extend_from_slice(&(bin.len() as u32).to_le_bytes());
        out.extend_from_slice(b"BIN\0");
        out.extend_from_slice(&bin);
        out
    }
}

pub(crate) fn load(bytes: &[u8]) -> Scene {
    load_bytes(Path::new("motion.glb"), bytes, &LoadOptions::default()).expect("loads")
}

/// A Khronos sample committed under tests/data/khronos/motion/ (`name`: its file name).
pub(crate) fn sample(name: &str) -> Scene {
    committed(&format!("tests/data/khronos/motion/{name}"))
}

/// A committed test file, by its path from the repository's root, loaded.
pub(crate) fn committed(path: &str) -> Scene {
    let path = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../..")).join(path);
    let bytes = std::fs::read(&path).expect("committed test file");
    load_bytes(&path, &bytes, &LoadOptions::default()).expect("loads")
}

/// Vertex i of mesh m in the file's coordinates (re-centring undone).
fn at(s: &Scene, m: usize, i: usize) -> Vec3 {
    Vec3::from(s.meshes[m].vertices[i].position) + s.origin.as_vec3()
}

/// Asserts that one of `s`'s warnings contains every one of `parts`.
fn warns(s: &Scene, parts: &[&str]) {
    assert!(
        s.warnings
            .iter()
            .any(|w| parts.iter().all(|p| w.message.contains(p))),
        "no warning with {parts:?}: {:?}",
        s.warnings
    );
}

fn normal(s: &Scene, m: usize, i: usize) -> Vec3 {
    Vec3::from(s.meshes[m].vertices[i].normal)
}

fn near(a: Vec3, b: Vec3) {
    assert!((a - b).length() < 1e-5, "{a} != {b}");
}

const TRIANGLE: [f32; 9] = [0.0, 0.0, 0.0, 0.0, 2.0, 0.0, 1.0, 0.0, 0.0];

/// A triangle skinned to two joints: joint 1 sits 1 up the Y axis and its node turns it 90°
/// about Z — a pose away from the bind pose the inverse bind matrices describe (joint 1 at
/// (0, 1, 0), unturned). The skinned node's own translation (100, 0, 0) must be ignored.
fn skinned(joints: &[u16], inverse_bind: &[f32]) -> Vec<u8> {
    let mut g = Glb::default();
    let pos = g.floats(&TRIANGLE, "VEC3", 3);
    let nrm = g.floats(&[1.0, 0.0, 0.0].repeat(3), "VEC3", 3);
    let j = g.u16s(joints, "VEC4");
    let w = g.floats(
        &[1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.5, 0.5, 0.0, 0.0],
        "VEC4",
        3,
    );
    let ibm = g.floats(inverse_bind, "MAT4", 2);
    let s = std::f32::consts::FRAC_1_SQRT_2;
    g.bytes(&format!(
        r#""scene":0,"scenes":[{{"nodes":[0,1]}}],
"nodes":[{{"mesh":0,"skin":0,"translation":[100,0,0]}},{{"children":[2]}},
{{"translation":[0,1,0],"rotation":[0,0,{s},{s}]}}],
"skins":[{{"joints":[1,2],"inverseBindMatrices":{ibm}}}],
"meshes":[{{"primitives":[{{"attributes":{{"POSITION":{pos},"NORMAL":{nrm},"JOINTS_0":{j},"WEIGHTS_0":{w}}}}}]}}]"#
    ))
}

const IDENTITY_AND_DOWN_1: [f32; 32] = [
    1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, //
    1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, -1.0, 0.0, 1.0,
];
const JOINTS: [u16; 12] = [0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0];

#[test]
fn a_skin_is_posed_by_its_joints_not_its_bind_pose_or_its_node() {
    let s = load(&skinned(&JOINTS, &IDENTITY_AND_DOWN_1));
    assert!(s.warnings.is_empty(), "{:?}", s.warnings);
    // J1 = T(0,1,0)·Rz(90°)·T(0,−1,0): (0,2,0) → (−1,1,0); (1,0,0) → (1,2,0), weighted
    // half with joint 0 (identity): (1,1,0).
    near(at(&s, 0, 0), Vec3::ZERO);
    near(at(&s, 0, 1), Vec3::new(-1.0, 1.0, 0.0));
    near(at(&s, 0, 2), Vec3::new(1.0, 1.0, 0.0));
    // Normals are skinned too: turned 90° with joint 1, 45° under the half-and-half matrix.
    near(normal(&s, 0, 0), Vec3::X);
    near(normal(&s, 0, 1), Vec3::Y);
    near(normal(&s, 0, 2), Vec3::new(1.0, 1.0, 0.0).normalize());
    assert!(
        s.maps.iter().any(|l| l == "skin 0: 2 joints"),
        "{:?}",
        s.maps
    );
}

#[test]
fn a_skin_with_joints_out_of_range_or_a_singular_bind_matrix_is_drawn_unskinned() {
    let mut bad = JOINTS;
    bad[4] = 7;
    let s = load(&skinned(&bad, &IDENTITY_AND_DOWN_1));
    warns(&s, &["names joint 7"]);
    // Unskinned: the node's transform carries it (translation 100 along X).
    near(at(&s, 0, 1), Vec3::new(100.0, 2.0, 0.0));
    let mut singular = IDENTITY_AND_DOWN_1;
    singular[16..32].fill(0.0);
    let s = load(&skinned(&JOINTS, &singular));
    warns(
        &s,
        &["skin 0: the inverse bind matrix of joint 1 is not invertible"],
    );
    near(at(&s, 0, 1), Vec3::new(100.0, 2.0, 0.0));
}

/// A triangle with two morph targets (target 0 lifts every vertex 2 along Z, target 1 moves
/// it 4 along X), `mesh_weights` and `node_weights` as given, and an animation of the
/// weights (LINEAR, keys at 0 and 2 s: [0, 0] then [1, 0.5]) and of the node's translation
/// (STEP: (0,0,0) then (0,10,0) from 1 s).
fn morphed(mesh_weights: &str, node_weights: &str) -> Vec<u8> {
    let mut g = Glb::default();
    let pos = g.floats(&TRIANGLE, "VEC3", 3);
    let up = g.floats(&[0.0, 0.0, 2.0].repeat(3), "VEC3", 3);
    let side = g.floats(&[4.0, 0.0, 0.0].repeat(3), "VEC3", 3);
    let t = g.floats(&[0.0, 2.0], "SCALAR", 2);
    let wv = g.floats(&[0.0, 0.0, 1.0, 0.5], "SCALAR", 4);
    let st = g.floats(&[0.0, 1.0], "SCALAR", 2);
    let tv = g.floats(&[0.0, 0.0, 0.0, 0.0, 10.0, 0.0], "VEC3", 2);
    g.bytes(&format!(
        r#""scene":0,"scenes":[{{"nodes":[0]}}],"nodes":[{{"mesh":0{node_weights}}}],
"meshes":[{{"primitives":[{{"attributes":{{"POSITION":{pos}}},
"targets":[{{"POSITION":{up}}},{{"POSITION":{side}}}]}}]{mesh_weights}}}],
"animations":[{{"name":"Wave","channels":[{{"sampler":0,"target":{{"node":0,"path":"weights"}}}},
{{"sampler":1,"target":{{"node":0,"path":"translation"}}}}],
"samplers":[{{"input":{t},"output":{wv}}},{{"input":{st},"output":{tv},"interpolation":"STEP"}}]}}]"#
    ))
}

#[test]
fn morph_weights_come_from_the_node_else_the_mesh() {
    let s = load(&morphed(r#","weights":[0.25,0]"#, ""));
    near(at(&s, 0, 1), Vec3::new(0.0, 2.0, 0.5));
    let s = load(&morphed(
        r#","weights":[0.25,0]"#,
        r#","weights":[0.75,0.5]"#,
    ));
    near(at(&s, 0, 1), Vec3::new(2.0, 2.0, 1.5));
    assert!(s.maps.iter().any(|l| l == "mesh 0: 2 morph targets"));
    assert!(s
        .maps
        .iter()
        .any(|l| l == "animation 0 \"Wave\": 2 channels, 2.000 s"));
}

#[test]
fn an_animation_poses_weights_and_nodes_at_any_moment_and_the_static_pose_returns() {
    let mut s = load(&morphed("", ""));
    let rest: Vec<_> = s.meshes[0].vertices.clone();
    let rest_bounds = s.bounds;
    // At 0.5 s the weights are a quarter of the way: [0.25, 0.125]; the STEP translation
    // still holds its first key.
    let changed = s
        .pose(Some(Moment {
            animation: 0,
            seconds: 0.5,
        }))
        .unwrap();
    assert_eq!(changed, vec![0]);
    near(at(&s, 0, 1), Vec3::new(0.5, 2.0, 0.5));
    let framing = s.bounds;
    // At 1.5 s: [0.75, 0.375] and the node has stepped up 10.
    s.pose(Some(Moment {
        animation: 0,
        seconds: 1.5,
    }))
    .unwrap();
    near(at(&s, 0, 1), Vec3::new(1.5, 12.0, 1.5));
    // Past the end: the last keys, held.
    s.pose(Some(Moment {
        animation: 0,
        seconds: 9.0,
    }))
    .unwrap();
    near(at(&s, 0, 1), Vec3::new(2.0, 12.0, 2.0));
    // The framing bounds are the animation's, whatever the moment, and hold every pose.
    assert_eq!(s.bounds, framing);
    assert!(framing.max.y - framing.min.y >= 12.0 - 1e-4);
    s.pose(None).unwrap();
    assert_eq!(s.meshes[0].vertices, rest);
    assert_eq!(s.bounds, rest_bounds);
    assert!(s
        .pose(Some(Moment {
            animation: 1,
            seconds: 0.0
        }))
        .is_err());
}

#[test]
fn the_same_moment_gives_the_same_vertices() {
    let mut a = load(&skinned(&JOINTS, &IDENTITY_AND_DOWN_1));
    let mut b = a.clone();
    let m = Some(Moment {
        animation: 0,
        seconds: 0.3,
    });
    // No animation in this file: a moment of it is refused, the static pose is kept.
    assert!(a.pose(m).is_err());
    a.pose(None).unwrap();
    b.pose(None).unwrap();
    assert_eq!(a.meshes[0].vertices, b.meshes[0].vertices);
}

/// A one-triangle file whose animation 0 has one translation channel with the given input
/// accessor (time data and claimed count) and output data.
fn one_channel(times: &[f32], count: usize, values: &[f32], interp: &str) -> Scene {
    one_channel_on(times, count, values, (interp, "translation"))
}

fn one_channel_on(
    times: &[f32],
    count: usize,
    values: &[f32],
    (interp, path): (&str, &str),
) -> Scene {
    let mut g = Glb::default();
    let pos = g.floats(&TRIANGLE, "VEC3", 3);
    let t = g.floats(times, "SCALAR", count);
    let v = g.floats(values, "VEC3", values.len() / 3);
    load(&g.bytes(&format!(
        r#""scene":0,"scenes":[{{"nodes":[0]}}],"nodes":[{{"mesh":0}}],
"meshes":[{{"primitives":[{{"attributes":{{"POSITION":{pos}}}}}]}}],
"animations":[{{"channels":[{{"sampler":0,"target":{{"node":0,"path":"{path}"}}}}],
"samplers":[{{"input":{t},"output":{v},"interpolation":"{interp}"}}]}}]"#
    )))
}

#[test]
fn hostile_samplers_are_dropped_with_a_warning() {
    let warned = |s: &Scene, what: &str| {
        warns(s, &[what, "animation 0 channel 0"]);
        assert_eq!(s.animations()[0].channels, 0);
    };
    let six = [0.0; 6];
    warned(
        &one_channel(&[0.0, f32::NAN], 2, &six, "LINEAR"),
        "not finite",
    );
    warned(&one_channel(&[1.0, 0.5], 2, &six, "LINEAR"), "go back");
    warned(
        &one_channel(&[0.0, 1.0], 2, &[0.0; 9], "LINEAR"),
        "3 output values for 2 keys",
    );
    warned(
        &one_channel(&[0.0, 1.0], 2, &six, "CUBICSPLINE"),
        "three per key",
    );
    warned(
        &one_channel(
            &[0.0, 1.0],
            2,
            &[0.0, f32::INFINITY, 0.0, 0.0, 0.0, 0.0],
            "STEP",
        ),
        "not finite",
    );
    // Words glTF does not define (the gltf crate's own accessors would panic on them: found
    // by the fuzz target).
    warned(
        &one_channel_on(&[0.0, 1.0], 2, &six, ("LINEAR", "translataon")),
        "target path",
    );
    // Ten million keys claimed over eight bytes: refused before anything is allocated.
    warned(
        &one_channel(&[0.0, 1.0], 10_000_000, &six, "LINEAR"),
        "10000000 keys",
    );
}

#[test]
fn a_joint_outside_the_drawn_scene_leaves_the_skin_unapplied() {
    let mut g = Glb::default();
    let pos = g.floats(&TRIANGLE, "VEC3", 3);
    let j = g.u16s(&[0; 12], "VEC4");
    let w = g.floats(&[1.0, 0.0, 0.0, 0.0].repeat(3), "VEC4", 3);
    // Node 1 is a joint but no scene lists it (nor does any node): its transform is not
    // defined in the drawn scene.
    let s = load(&g.bytes(&format!(
        r#""scene":0,"scenes":[{{"nodes":[0]}}],"nodes":[{{"mesh":0,"skin":0}},{{"translation":[5,0,0]}}],
"skins":[{{"joints":[1]}}],
"meshes":[{{"primitives":[{{"attributes":{{"POSITION":{pos},"JOINTS_0":{j},"WEIGHTS_0":{w}}}}}]}}]"#
    )));
    warns(&s, &["skin 0: joint node 1 is not in the drawn scene"]);
    near(at(&s, 0, 1), Vec3::new(0.0, 2.0, 0.0));
}

/// A triangle with normals, tangents, UVs and colours whose node's scale goes 1, 0 and
/// (2, 0.5, 1) (LINEAR, keys at 0, 1 and 2 s): at 1 s its normal matrix is singular, so
/// there its normals are generated (the loader's path for a mesh without usable normals);
/// after, the unequal scale turns its tangents.
fn shrinking() -> Vec<u8> {
    let mut g = Glb::default();
    let pos = g.floats(&TRIANGLE, "VEC3", 3);
    let nrm = g.floats(&[0.0, 0.0, 1.0].repeat(3), "VEC3", 3);
    let tan = g.floats(&[0.6, 0.8, 0.0, -1.0].repeat(3), "VEC4", 3);
    let uv = g.floats(&[0.0, 0.0, 0.0, 1.0, 1.0, 0.0], "VEC2", 3);
    let col = g.floats(&[1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0], "VEC3", 3);
    let t = g.floats(&[0.0, 1.0, 2.0], "SCALAR", 3);
    let sv = g.floats(&[1.0, 1.0, 1.0, 0.0, 0.0, 0.0, 2.0, 0.5, 1.0], "VEC3", 3);
    g.bytes(&format!(
        r#""scene":0,"scenes":[{{"nodes":[0]}}],"nodes":[{{"mesh":0}}],
"meshes":[{{"primitives":[{{"attributes":{{"POSITION":{pos},"NORMAL":{nrm},"TANGENT":{tan},
"TEXCOORD_0":{uv},"COLOR_0":{col}}}}}]}}],
"animations":[{{"channels":[{{"sampler":0,"target":{{"node":0,"path":"scale"}}}}],
"samplers":[{{"input":{t},"output":{sv}}}]}}]"#
    ))
}

/// A pose writes the scene's meshes in place only where they keep the layout the file's
/// normals give, and the result is, field for field, the mesh the loader's path builds
/// anew at that moment ([`crate::motion::Rig::posed_meshes_except`]); in place, the streams a pose
/// does not move (the indices, the colours) are the same allocation. Where normals are
/// generated (the shrunk node at 1 s) and in the pose after, the mesh is built anew.
#[test]
fn a_pose_in_place_is_the_mesh_built_anew_and_keeps_the_streams_that_do_not_move() {
    let rigged = sample("RiggedSimple.glb");
    let shrunk = [
        (0.5, true),
        (1.0, false),
        (1.5, false),
        (1.7, true),
        (0.2, true),
    ];
    let rig_times = [(0.3, true), (1.1, true), (0.0, true)];
    for (mut s, times) in [(load(&shrinking()), &shrunk[..]), (rigged, &rig_times[..])] {
        let rig = s.motion.clone().expect("a rig");
        let loaded: Vec<String> = s.meshes.iter().map(|m| format!("{m:?}")).collect();
        for &(seconds, in_place) in times {
            let m = Some(Moment {
                animation: 0,
                seconds,
            });
            let before: Vec<*const u32> = s.meshes.iter().map(|m| m.indices.as_ptr()).collect();
            let changed = s.pose(m).expect("poses");
            let fresh = rig.posed_meshes_except(m, &[]).expect("poses");
            assert!(!fresh.is_empty());
            assert_eq!(changed, fresh.iter().map(|f| f.0).collect::<Vec<_>>());
            for (i, f) in fresh {
                assert_eq!(
                    format!("{:?}", s.meshes[i]),
                    format!("{f:?}"),
                    "{seconds} s"
                );
                let kept = s.meshes[i].indices.as_ptr() == before[i];
                assert_eq!(kept, in_place, "mesh {i} at {seconds} s");
            }
        }
        s.pose(None).expect("poses");
        let back: Vec<String> = s.meshes.iter().map(|m| format!("{m:?}")).collect();
        assert_eq!(back, loaded, "the static pose is the loaded mesh again");
    }
}

/// `--xray` of a moving object gives its mesh a material of its own, which a pose keeps,
/// whether it writes the mesh in place (0.5 s) or makes it anew (1 s: normals generated).
#[test]
fn a_pose_keeps_an_xrayed_objects_material() {
    let mut s = load(&shrinking());
    s.xray(&["mesh".into()], 0.3).expect("the object is there");
    let xrayed = s.meshes[0].material;
    assert_eq!(
        s.materials[xrayed].name,
        format!("{} (x-ray)", s.materials[0].name)
    );
    for seconds in [0.5, 1.0, 1.7] {
        s.pose(Some(Moment {
            animation: 0,
            seconds,
        }))
        .expect("poses");
        assert_eq!(s.meshes[0].material, xrayed, "{seconds} s");
    }
}

/// From one moment to another, a pose rewrites only the meshes either moment's animation
/// moves (InterpolationTest: nine cubes, each moved by one of nine animations); from or to
/// the static pose, every moving mesh. The meshes left alone are what a pose would write.
#[test]
fn a_pose_rewrites_only_the_meshes_its_animations_move() {
    let mut s = sample("InterpolationTest.glb");
    let rig = s.motion.clone().expect("a rig");
    let all = rig.meshes().to_vec();
    assert_eq!(all.len(), 9);
    let at = |animation, seconds| Some(Moment { animation, seconds });
    assert_eq!(
        s.pose(at(0, 0.5)).expect("poses"),
        all,
        "from the static pose"
    );
    let one = s.pose(at(0, 0.9)).expect("poses");
    assert_eq!(one.len(), 1, "{one:?}");
    let other = s.pose(at(4, 0.3)).expect("poses");
    assert_eq!(other.len(), 2, "{other:?}");
    assert!(
        other.contains(&one[0]),
        "animation 0's cube goes back to rest"
    );
    for m in [at(4, 0.6), at(7, 1.0), at(7, 1.2)] {
        s.pose(m).expect("poses");
        for (i, fresh) in rig.posed_meshes_except(m, &[]).expect("poses") {
            assert_eq!(format!("{:?}", s.meshes[i]), format!("{fresh:?}"), "{m:?}");
        }
    }
    assert_eq!(s.pose(None).expect("poses"), all, "to the static pose");
}

/// The skinned triangle of [`skinned`] with two morph targets moving positions and normals
/// (`normals`: with normal deltas): four delta attributes, or two without.
fn skinned_morphed(normals: bool) -> Vec<u8> {
    let mut g = Glb::default();
    let pos = g.floats(&TRIANGLE, "VEC3", 3);
    let nrm = g.floats(&[1.0, 0.0, 0.0].repeat(3), "VEC3", 3);
    let j = g.u16s(&JOINTS, "VEC4");
    let w = g.floats(
        &[1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.5, 0.5, 0.0, 0.0],
        "VEC4",
        3,
    );
    let ibm = g.floats(&IDENTITY_AND_DOWN_1, "MAT4", 2);
    let up = g.floats(&[0.0, 0.0, 2.0].repeat(3), "VEC3", 3);
    let side = g.floats(&[4.0, 0.0, 0.0].repeat(3), "VEC3", 3);
    let tilt = g.floats(&[0.0, 0.0, 0.5].repeat(3), "VEC3", 3);
    let n = |a: usize| {
        if normals {
            format!(r#","NORMAL":{a}"#)
        } else {
            String::new()
        }
    };
    let s = std::f32::consts::FRAC_1_SQRT_2;
    g.bytes(&format!(
        r#""scene":0,"scenes":[{{"nodes":[0,1]}}],
"nodes":[{{"mesh":0,"skin":0}},{{"children":[2]}},
{{"translation":[0,1,0],"rotation":[0,0,{s},{s}]}}],
"skins":[{{"joints":[1,2],"inverseBindMatrices":{ibm}}}],
"meshes":[{{"primitives":[{{"attributes":{{"POSITION":{pos},"NORMAL":{nrm},"JOINTS_0":{j},"WEIGHTS_0":{w}}},
"targets":[{{"POSITION":{up}{}}},{{"POSITION":{side}{}}}]}}],"weights":[0.5,0.25]}}]"#,
        n(tilt),
        n(tilt)
    ))
}

/// A part both skinned and morphed goes to the GPU as one draw (its real skin's joints and
/// JOINTS_0/WEIGHTS_0, and its targets' deltas) when the skin fits the joint budget and the
/// deltas the free attributes; over either, the CPU with the reason.
#[test]
fn a_skinned_and_morphed_part_is_decided_by_both_budgets() {
    use crate::motion::gpu::{CpuBecause, MorphKind};
    let s = load(&skinned_morphed(true));
    assert!(s.warnings.is_empty(), "{:?}", s.warnings);
    let rig = s.motion.clone().expect("a rig");
    let (gpu, cpu) = rig.gpu_skinned(&s, 2, 4);
    assert!(cpu.is_empty(), "{cpu:?}");
    let g = &gpu[0];
    assert_eq!((g.mesh, g.skin, g.joints), (0, 0, 2));
    assert_eq!(g.joint_ids[1], [1.0, 0.0, 0.0, 0.0]);
    assert_eq!(g.weights[2], [0.5, 0.5, 0.0, 0.0]);
    let m = g.morph.as_ref().expect("morphed with its skin");
    use MorphKind::{Normal, Position};
    assert_eq!(
        m.slots,
        vec![(Position, 0), (Position, 1), (Normal, 0), (Normal, 1)]
    );
    assert_eq!(
        (m.part, m.deltas[1][0], m.deltas[3][2]),
        (0, [4.0, 0.0, 0.0], [0.0, 0.0, 0.5])
    );
    let (gpu, cpu) = rig.gpu_skinned(&s, 1, 4);
    assert!(gpu.is_empty());
    assert_eq!(cpu, vec![(0, CpuBecause::OverBudget(2))]);
    let (gpu, cpu) = rig.gpu_skinned(&s, 2, 3);
    assert!(gpu.is_empty());
    assert_eq!(cpu, vec![(0, CpuBecause::MorphOverBudget(4))]);
    // Position deltas only: two attributes, which fit 3.
    let s = load(&skinned_morphed(false));
    let rig = s.motion.clone().expect("a rig");
    let (gpu, _) = rig.gpu_skinned(&s, 2, 3);
    let m = gpu[0].morph.as_ref().expect("morphed with its skin");
    assert_eq!(m.slots, vec![(Position, 0), (Position, 1)]);
    // A skinned part without targets is plain skinning (no morph attributes).
    let s = load(&skinned(&JOINTS, &IDENTITY_AND_DOWN_1));
    let rig = s.motion.clone().expect("a rig");
    let (gpu, _) = rig.gpu_skinned(&s, 2, 0);
    assert!(gpu[0].morph.is_none());
}

/// Node 0 holds a triangle, its three edges as LINES and its corners as POINTS, all on the
/// same positions and normals (+X: the points are lit); an animation moves the node: translation (0,0,0) →
/// (4,0,0) → (4,2,0) (LINEAR, keys at 0, 1, 2 s) and a turn of 90° about Z from 1 s (STEP).
/// Node 1's lines never move.
fn moving_wire() -> Vec<u8> {
    let mut g = Glb::default();
    let pos = g.floats(&TRIANGLE, "VEC3", 3);
    let nrm = g.floats(&[1.0, 0.0, 0.0].repeat(3), "VEC3", 3);
    let edges = g.u16s(&[0, 1, 1, 2, 2, 0], "SCALAR");
    let far = g.floats(&[10.0, 0.0, 0.0, 10.0, 1.0, 0.0], "VEC3", 2);
    let far_nrm = g.floats(&[1.0, 0.0, 0.0].repeat(2), "VEC3", 2);
    let t3 = g.floats(&[0.0, 1.0, 2.0], "SCALAR", 3);
    let tv = g.floats(&[0.0, 0.0, 0.0, 4.0, 0.0, 0.0, 4.0, 2.0, 0.0], "VEC3", 3);
    let t2 = g.floats(&[0.0, 1.0], "SCALAR", 2);
    let s = std::f32::consts::FRAC_1_SQRT_2;
    let rv = g.floats(&[0.0, 0.0, 0.0, 1.0, 0.0, 0.0, s, s], "VEC4", 2);
    g.bytes(&format!(
        r#""scene":0,"scenes":[{{"nodes":[0,1]}}],"nodes":[{{"mesh":0}},{{"mesh":1}}],
"meshes":[{{"primitives":[{{"attributes":{{"POSITION":{pos},"NORMAL":{nrm}}}}},
{{"attributes":{{"POSITION":{pos},"NORMAL":{nrm}}},"indices":{edges},"mode":1}},
{{"attributes":{{"POSITION":{pos},"NORMAL":{nrm}}},"mode":0}}]}},
{{"primitives":[{{"attributes":{{"POSITION":{far},"NORMAL":{far_nrm}}},"mode":1}}]}}],
"animations":[{{"channels":[{{"sampler":0,"target":{{"node":0,"path":"translation"}}}},
{{"sampler":1,"target":{{"node":0,"path":"rotation"}}}}],
"samplers":[{{"input":{t3},"output":{tv}}},{{"input":{t2},"output":{rv},"interpolation":"STEP"}}]}}]"#
    ))
}

/// Wire position `i` of `s` in the file's coordinates (re-centring undone).
fn wire_at(s: &Scene, i: usize) -> Vec3 {
    Vec3::from(s.wire.positions[i]) + s.origin.as_vec3()
}

/// Lines and points of a moving node move with it, as its triangles do: at 1.5 s every
/// corner is the turned, moved triangle's, (x, y) → (4 − y, 1 + x) by hand, and the points'
/// normals turn from +X to +Y; the still node's lines stay; the static pose puts them back;
/// the animation's framing bounds hold every moved line.
#[test]
fn lines_and_points_of_a_moving_node_move_with_it() {
    let mut s = load(&moving_wire());
    // The lines and the points (3 positions each), the still lines (2).
    assert_eq!(s.wire.positions.len(), 8);
    assert_eq!(s.wire.normals.len(), 8, "lit points");
    let rest: Vec<Vec3> = (0..8).map(|i| wire_at(&s, i)).collect();
    let rest_normals = s.wire.normals.clone();
    let (still, moving): (Vec<usize>, Vec<usize>) = (0..8).partition(|&i| rest[i].x > 5.0);
    assert_eq!(still.len(), 2);
    let corner = |i: usize| rest[i];
    assert!(moving.iter().all(|&i| TRIANGLE
        .chunks_exact(3)
        .any(|c| (Vec3::from_slice(c) - corner(i)).length() < 1e-5)));
    s.pose(Some(Moment {
        animation: 0,
        seconds: 1.5,
    }))
    .unwrap();
    for &i in &moving {
        let c = corner(i);
        let want = Vec3::new(4.0 - c.y, 1.0 + c.x, c.z);
        near(wire_at(&s, i), want);
        near(Vec3::from(s.wire.normals[i]), Vec3::Y);
        let q = want - s.origin.as_vec3();
        let inside = q.cmpge(s.bounds.min - 1e-4).all() && q.cmple(s.bounds.max + 1e-4).all();
        assert!(inside, "{want} outside the framing bounds {:?}", s.bounds);
    }
    for &i in &still {
        near(wire_at(&s, i), rest[i]);
        near(Vec3::from(s.wire.normals[i]), Vec3::X);
    }
    s.pose(None).unwrap();
    for (i, r) in rest.iter().enumerate() {
        near(wire_at(&s, i), *r);
    }
    assert_eq!(s.wire.normals, rest_normals);
}

/// The copies of an instanced node (EXT_mesh_gpu_instancing) under a moving node move with
/// it (tests/data/motion/MovingWire.glb: node 5 draws a cube scaled 0.3 at x = −0.8, 0, 0.8,
/// 0.9 above node 0, which is moved by (1.5, 0.5, 0) and turned 30° about Y at 1 s): each
/// copy's centre is then (1.5 + 0.866·x, 1.4, −0.5·x) by hand; its record is no longer
/// shared (the renderer draws the copies as they are, not as instances of the first).
#[test]
fn copies_of_an_instanced_node_move_with_it() {
    let mut s = committed("tests/data/motion/MovingWire.glb");
    let copies = |s: &Scene| -> Vec<Vec3> {
        let mut c: Vec<Vec3> = (0..s.meshes.len())
            .filter_map(|m| {
                let mut b = crate::model::Bounds::empty();
                for v in &s.meshes[m].vertices {
                    b.include(v.position.into());
                }
                let size = b.max - b.min;
                ((size.y - 0.3).abs() < 1e-4).then(|| b.center() + s.origin.as_vec3())
            })
            .collect();
        c.sort_by(|a, b| a.x.total_cmp(&b.x));
        c
    };
    let rest = copies(&s);
    assert_eq!(rest.len(), 3, "three copies");
    for (c, x) in rest.iter().zip([-0.8f32, 0.0, 0.8]) {
        near(*c, Vec3::new(x, 0.9, 0.0));
    }
    s.pose(Some(Moment {
        animation: 0,
        seconds: 1.0,
    }))
    .unwrap();
    let (cos, sin) = (30f32.to_radians().cos(), 30f32.to_radians().sin());
    let moved = copies(&s);
    assert_eq!(moved.len(), 3, "three copies at 1 s");
    for (c, x) in moved.iter().zip([-0.8f32, 0.0, 0.8]) {
        near(*c, Vec3::new(1.5 + cos * x, 1.4, -sin * x));
    }
    let record = s.instancing.iter().find(|r| r.node == 5).expect("node 5");
    assert!(!record.shareable(), "a moving node's copies are not shared");
    // The copies are posed from one source, read (and charged to the morph budget) once.
    let rig = s.motion.clone().unwrap();
    let sources: Vec<_> = rig
        .parts
        .iter()
        .filter(|p| p.by.node == 5)
        .map(|p| &p.by.src)
        .collect();
    assert_eq!(sources.len(), 3);
    assert!(sources
        .iter()
        .all(|q| std::sync::Arc::ptr_eq(q, sources[0])));
    s.pose(None).unwrap();
    assert_eq!(copies(&s), rest);
}

/// A skin with two joint sets (tests/data/motion/TwoJointSets.glb from
/// scripts/make_two_joint_sets.py: up to six joints per vertex, split between JOINTS_0 and
/// JOINTS_1 differently on alternate rings) is posed by both sets: at 1 s every vertex is
/// where the script, computing apart from glview, puts it (TwoJointSets.expected.json),
/// within 4e-6 (the tube is 4 high); set 0 alone puts a vertex 3.5 off.
#[test]
fn a_skin_with_two_joint_sets_is_posed_by_both() {
    let mut s = committed("tests/data/motion/TwoJointSets.glb");
    let text = std::fs::read_to_string(
        Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
            .join("tests/data/motion/TwoJointSets.expected.json"),
    )
    .expect("expected positions");
    let json: serde_json::Value = serde_json::from_str(&text).unwrap();
    let want: Vec<Vec3> = json["positions"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| {
            let c: Vec<f32> = p
                .as_array()
                .unwrap()
                .iter()
                .map(|x| x.as_f64().unwrap() as f32)
                .collect();
            Vec3::from_slice(&c)
        })
        .collect();
    let rest: Vec<Vec3> = (0..want.len()).map(|i| at(&s, 0, i)).collect();
    s.pose(Some(Moment {
        animation: 0,
        seconds: 1.0,
    }))
    .unwrap();
    assert_eq!(s.meshes[0].vertices.len(), want.len());
    let worst = (0..want.len())
        .map(|i| (at(&s, 0, i) - want[i]).length())
        .fold(0.0f32, f32::max);
    assert!(worst < 4e-6, "a vertex is {worst} from the script's pose");
    let moved = (0..want.len())
        .map(|i| (want[i] - rest[i]).length())
        .fold(0.0f32, f32::max);
    assert!(moved > 0.5, "the pose at 1 s moves the tube: {moved}");
}
