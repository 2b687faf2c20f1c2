//! penumbra-scene: the scene model shared by every backend, and its loaders
//! (glTF 2.0, OBJ + MTL, the native TOML format).
//!
//! Data flows one way: file → [`Scene`] → backend. Loaders validate input and
//! return a [`SceneError`] that names the file, the place in it and what is
//! wrong; a loaded `Scene` is well-formed (finite positions, indices in range,
//! no degenerate triangles, materials and textures that exist).

pub mod builtin;
pub mod camera;
pub mod environment;
pub mod error;
pub mod fingerprint;
pub mod load;
pub mod material;
pub mod mesh;
pub mod mipmap;
pub mod paths;
pub mod plane;
pub mod primitives;
pub mod scene;
pub mod settings;
pub mod tangents;
pub mod texture;

pub use camera::{Camera, FilmRays, Projection};
pub use environment::{EnvironmentChoice, LightCount, apply_environment};
pub use error::{Location, SceneError};
pub use fingerprint::{Fnv1a, fingerprint};
pub use load::{LoadOptions, load_scene};
pub use material::{AlphaCoverage, AlphaMode, Material, MaterialId, NormalMap, OcclusionMap};
pub use mesh::{Instance, Mesh, MeshId};
pub use plane::Plane;
pub use scene::{NamedCamera, Scene, SceneAreaLight, SceneLight};
pub use settings::{IntegratorKind, RenderSettings};
pub use texture::{Texels, Texture, TextureId};
