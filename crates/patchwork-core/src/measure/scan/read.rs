//! Reading a scan: PLY (ASCII or binary: its `vertex` element's x, y, z
//! and its `face` element's vertex indices, if any), OBJ, STL (ASCII or
//! binary) or XYZ text (the first three numbers of each line; more columns
//! — normals, colours — are ignored). A mesh (faces given) is sampled
//! uniformly over its area, at least `MESH_SAMPLES` points (seeded): a
//! mesh's vertices may be sparse and uneven, a centreline's cross-sections
//! need points everywhere. The formats are told apart by the file's name.

use std::io::{BufRead, BufReader, Cursor};

use ply_rs_bw::parser::{Parser, Reader};
use ply_rs_bw::ply::{PropertyAccess, PropertyAccessResult};

use super::ScanError;
use crate::cmaes::SeededRng;
use crate::curve::{Point, Units};

/// Points sampled over a mesh's faces, at least (as many as it has
/// vertices when more, up to `MAX_MESH_SAMPLES`).
const MESH_SAMPLES: usize = 300_000;
const MAX_MESH_SAMPLES: usize = 3_000_000;

/// A scan as read: points, and triangles over them when it is a mesh.
struct Surface {
    vertices: Vec<Point>,
    triangles: Vec<[usize; 3]>,
}

/// The scan formats, by file extension.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ScanFormat {
    Ply,
    Obj,
    Stl,
    Xyz,
}

impl ScanFormat {
    /// The format a file's name says (`.ply`, `.obj`, `.stl`, `.xyz`,
    /// `.pts`; any case); none for another name (a centreline's `.csv`,
    /// `.txt`, `.json`).
    pub fn from_name(name: &str) -> Option<ScanFormat> {
        let extension = name.rsplit('.').next()?.to_ascii_lowercase();
        match extension.as_str() {
            "ply" => Some(ScanFormat::Ply),
            "obj" => Some(ScanFormat::Obj),
            "stl" => Some(ScanFormat::Stl),
            "xyz" | "pts" => Some(ScanFormat::Xyz),
            _ => None,
        }
    }
}

/// The points of a scan file's bytes, in mm.
pub fn read_scan(bytes: &[u8], format: ScanFormat, units: Units) -> Result<Vec<Point>, ScanError> {
    let surface = match format {
        ScanFormat::Ply => read_ply(bytes)?,
        ScanFormat::Obj => read_obj(bytes)?,
        ScanFormat::Stl => read_stl(bytes)?,
        ScanFormat::Xyz => Surface {
            vertices: read_xyz(bytes)?,
            triangles: Vec::new(),
        },
    };
    let points = sampled(surface)?;
    let scale = units.to_mm();
    Ok(points.into_iter().map(|p| p * scale).collect())
}

#[derive(Default)]
struct Vertex([f64; 3]);

/// A PLY face: its vertex indices (`vertex_indices` or `vertex_index`).
#[derive(Default)]
struct Face(Vec<i64>);

impl PropertyAccess for Face {
    fn new() -> Self {
        Face::default()
    }
    fn set_list_int(&mut self, name: &str, value: Vec<i32>) -> PropertyAccessResult {
        self.set(name, value.into_iter().map(i64::from).collect())
    }
    fn set_list_uint(&mut self, name: &str, value: Vec<u32>) -> PropertyAccessResult {
        self.set(name, value.into_iter().map(i64::from).collect())
    }
}

impl Face {
    fn set(&mut self, name: &str, indices: Vec<i64>) -> PropertyAccessResult {
        match name {
            "vertex_indices" | "vertex_index" => {
                self.0 = indices;
                PropertyAccessResult::Set
            }
            _ => PropertyAccessResult::Ignored,
        }
    }
}

impl PropertyAccess for Vertex {
    fn new() -> Self {
        Vertex::default()
    }
    fn set_float(&mut self, name: &str, value: f32) -> PropertyAccessResult {
        self.set_double(name, f64::from(value))
    }
    fn set_double(&mut self, name: &str, value: f64) -> PropertyAccessResult {
        match name {
            "x" => self.0[0] = value,
            "y" => self.0[1] = value,
            "z" => self.0[2] = value,
            _ => return PropertyAccessResult::Ignored,
        }
        PropertyAccessResult::Set
    }
}

fn read_ply(bytes: &[u8]) -> Result<Surface, ScanError> {
    let bad = |e: ply_rs_bw::parser::ParseError| {
        ScanError::Read(format!("not a PLY file we can read: {e}"))
    };
    let mut reader = Reader::new(BufReader::new(Cursor::new(bytes)));
    let parser = Parser::<Vertex>::new();
    let header = parser.read_header(&mut reader).map_err(bad)?;
    let Some(element) = header.elements.get("vertex") else {
        return Err(ScanError::Read(
            "the PLY file has no `vertex` element".into(),
        ));
    };
    for axis in ["x", "y", "z"] {
        if !element.properties.contains_key(axis) {
            return Err(ScanError::Read(format!(
                "the PLY file's vertices have no `{axis}`"
            )));
        }
    }
    let mut vertices = Vec::new();
    let mut faces = Vec::new();
    // Elements come in the header's order; each is read or skipped whole.
    for (name, element) in &header.elements {
        match name.as_str() {
            "vertex" => {
                vertices = parser
                    .read_payload_for_element(&mut reader, element, &header)
                    .map_err(bad)?
            }
            "face" => {
                faces = Parser::<Face>::new()
                    .read_payload_for_element(&mut reader, element, &header)
                    .map_err(bad)?
            }
            _ => break,
        }
    }
    let triangles = faces
        .iter()
        .flat_map(|f| (2..f.0.len()).map(move |k| [f.0[0], f.0[k - 1], f.0[k]]))
        .map(|t| t.map(|i| usize::try_from(i).unwrap_or(usize::MAX)))
        .collect();
    Ok(Surface {
        vertices: vertices.into_iter().map(|v| Point::from(v.0)).collect(),
        triangles,
    })
}

fn read_obj(bytes: &[u8]) -> Result<Surface, ScanError> {
    let mut reader = BufReader::new(Cursor::new(bytes));
    let options = tobj::LoadOptions {
        triangulate: true,
        single_index: true,
        ..tobj::LoadOptions::default()
    };
    let (models, _) = tobj::load_obj_buf(&mut reader, &options, |_| {
        Err(tobj::LoadError::OpenFileFailed)
    })
    .map_err(|e| ScanError::Read(format!("not an OBJ file we can read: {e}")))?;
    let mut surface = Surface {
        vertices: Vec::new(),
        triangles: Vec::new(),
    };
    for model in &models {
        let offset = surface.vertices.len();
        let positions = model.mesh.positions.chunks_exact(3);
        surface.vertices.extend(
            positions.map(|p| Point::new(f64::from(p[0]), f64::from(p[1]), f64::from(p[2]))),
        );
        let corners = model.mesh.indices.chunks_exact(3);
        surface
            .triangles
            .extend(corners.map(|t| [0, 1, 2].map(|k| offset + t[k] as usize)));
    }
    if surface.vertices.is_empty() {
        // A point cloud as OBJ: vertices without faces, which tobj skips.
        return Ok(Surface {
            vertices: obj_vertices(bytes)?,
            triangles: Vec::new(),
        });
    }
    Ok(surface)
}

/// The `v x y z` lines of an OBJ file.
fn obj_vertices(bytes: &[u8]) -> Result<Vec<Point>, ScanError> {
    let text = String::from_utf8_lossy(bytes);
    let lines = text.lines().filter(|l| l.trim_start().starts_with("v "));
    read_xyz(
        lines
            .map(|l| l.trim_start()[2..].to_string() + "\n")
            .collect::<String>()
            .as_bytes(),
    )
}

fn read_stl(bytes: &[u8]) -> Result<Surface, ScanError> {
    let mesh = stl_io::read_stl(&mut Cursor::new(bytes))
        .map_err(|e| ScanError::Read(format!("not an STL file we can read: {e}")))?;
    Ok(Surface {
        vertices: mesh
            .vertices
            .iter()
            .map(|v| Point::new(f64::from(v.0[0]), f64::from(v.0[1]), f64::from(v.0[2])))
            .collect(),
        triangles: mesh.faces.iter().map(|f| f.vertices).collect(),
    })
}

/// The points of `surface`: its vertices, or for a mesh points uniformly
/// over its area (seeded: the same file gives the same points).
fn sampled(surface: Surface) -> Result<Vec<Point>, ScanError> {
    let Surface {
        vertices,
        triangles,
    } = surface;
    if triangles.is_empty() {
        return Ok(vertices);
    }
    let n = vertices.len();
    if let Some((k, t)) = triangles
        .iter()
        .enumerate()
        .find(|(_, t)| t.iter().any(|&i| i >= n))
    {
        return Err(ScanError::Read(format!(
            "face {k} refers to vertex {} of {n}",
            t.iter().max().copied().unwrap_or(0)
        )));
    }
    let mut cumulative = Vec::with_capacity(triangles.len());
    let mut total = 0.0;
    for t in &triangles {
        let (a, b, c) = (vertices[t[0]], vertices[t[1]], vertices[t[2]]);
        total += 0.5 * (b - a).cross(&(c - a)).norm();
        cumulative.push(total);
    }
    if total.is_nan() || total <= 0.0 {
        return Ok(vertices);
    }
    let count = n.clamp(MESH_SAMPLES, MAX_MESH_SAMPLES);
    let mut rng = SeededRng::new(1);
    Ok((0..count)
        .map(|_| {
            let u = rng.uniform() * total;
            let t = triangles[cumulative
                .partition_point(|&c| c < u)
                .min(triangles.len() - 1)];
            let (mut x, mut y) = (rng.uniform(), rng.uniform());
            if x + y > 1.0 {
                (x, y) = (1.0 - x, 1.0 - y);
            }
            let a = vertices[t[0]];
            a + (vertices[t[1]] - a) * x + (vertices[t[2]] - a) * y
        })
        .collect())
}

/// `x y z [more]` per line, separated by spaces, tabs, commas or
/// semicolons; blank lines and lines starting with `#` or `//` skipped.
fn read_xyz(bytes: &[u8]) -> Result<Vec<Point>, ScanError> {
    let mut points = Vec::new();
    for (number, line) in BufReader::new(bytes).lines().enumerate() {
        let line = line.map_err(|e| ScanError::Read(format!("line {}: {e}", number + 1)))?;
        let text = line.trim();
        if text.is_empty() || text.starts_with('#') || text.starts_with("//") {
            continue;
        }
        let mut values = text
            .split(|c: char| c.is_whitespace() || c == ',' || c == ';')
            .filter(|v| !v.is_empty())
            .map(str::parse::<f64>);
        let mut xyz = [0.0; 3];
        for (axis, slot) in xyz.iter_mut().enumerate() {
            *slot = match values.next() {
                Some(Ok(v)) => v,
                Some(Err(_)) => {
                    return Err(ScanError::Read(format!(
                        "line {}: column {} is not a number",
                        number + 1,
                        axis + 1
                    )));
                }
                None => {
                    return Err(ScanError::Read(format!(
                        "line {}: expected x y z, found {} columns",
                        number + 1,
                        axis
                    )));
                }
            };
        }
        points.push(Point::from(xyz));
    }
    Ok(points)
}
