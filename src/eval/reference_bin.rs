//! `reference.bin`, the cache file of a reference: an 8-byte magic, the JSON header's length
//! (u32, little endian), the header ([`ReferenceHeader`]), then every sampled position of every
//! frame and the final vertices as f32 triples.

use super::{io_err, ReferenceError, ReferenceHeader};
use crate::sim::Trajectory;
use std::io::Read;
use std::path::Path;

/// The first bytes of every `reference.bin`.
pub(super) const MAGIC: &[u8; 8] = b"ACREF001";

/// Writes `reference.bin` atomically; returns the header as written (`data_hash` set).
pub fn write_bin(
    path: &Path,
    header: &ReferenceHeader,
    t: &Trajectory,
) -> Result<ReferenceHeader, ReferenceError> {
    let mut data = Vec::with_capacity(12 * (t.positions.len() + t.final_vertices.len()));
    for p in t.positions.iter().chain(&t.final_vertices) {
        for c in p {
            data.extend_from_slice(&c.to_le_bytes());
        }
    }
    let header = ReferenceHeader {
        data_hash: data_hash(&data),
        ..header.clone()
    };
    let json = serde_json::to_vec(&header).map_err(|e| ReferenceError::Malformed {
        path: path.display().to_string(),
        why: e.to_string(),
    })?;
    let mut bytes = Vec::with_capacity(12 + json.len() + data.len());
    bytes.extend_from_slice(MAGIC);
    bytes.extend_from_slice(&(json.len() as u32).to_le_bytes());
    bytes.extend_from_slice(&json);
    bytes.extend_from_slice(&data);
    crate::io::write_atomic(path, &bytes).map_err(io_err(path))?;
    Ok(header)
}

/// The checksum of a file's data: FNV-1a, 16 hex digits.
fn data_hash(data: &[u8]) -> String {
    format!("{:016x}", super::fnv1a(super::FNV_OFFSET, data))
}

/// Reads `reference.bin`: [`ReferenceError::Malformed`] when its header's counts disagree with
/// each other or with the data's size, its data does not match its checksum, or a position,
/// rest point or time is not finite.
pub fn read_bin(path: &Path) -> Result<(ReferenceHeader, Trajectory), ReferenceError> {
    let malformed = |why: &str| ReferenceError::Malformed {
        path: path.display().to_string(),
        why: why.to_string(),
    };
    let mut f = std::fs::File::open(path).map_err(io_err(path))?;
    let mut bytes = Vec::new();
    f.read_to_end(&mut bytes).map_err(io_err(path))?;
    if bytes.len() < 12 || &bytes[..8] != MAGIC {
        return Err(malformed("bad magic"));
    }
    let n = u32::from_le_bytes(bytes[8..12].try_into().expect("4 bytes")) as usize;
    let json = bytes
        .get(12..12 + n)
        .ok_or_else(|| malformed("short header"))?;
    let header: ReferenceHeader =
        serde_json::from_slice(json).map_err(|e| malformed(&e.to_string()))?;
    check_header(&header).map_err(|why| malformed(&why))?;
    let points = header.samples.len();
    let frames = header.times.len();
    let body = &bytes[12 + n..];
    let floats: Vec<f32> = body
        .chunks_exact(4)
        .map(|c| f32::from_le_bytes(c.try_into().expect("4 bytes")))
        .collect();
    let want = 3 * (frames * points + header.final_vertices);
    if floats.len() != want || body.len() % 4 != 0 {
        return Err(malformed(&format!(
            "{} floats, expected {want}",
            floats.len()
        )));
    }
    if let Some(k) = floats.iter().position(|x| !x.is_finite()) {
        return Err(malformed(&format!(
            "position value {k} is {}, expected a finite number",
            floats[k]
        )));
    }
    if !header.data_hash.is_empty() && data_hash(body) != header.data_hash {
        return Err(malformed(
            "its data does not match the checksum in its header (edited or corrupted)",
        ));
    }
    let triples: Vec<[f32; 3]> = floats.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect();
    let (positions, final_vertices) = triples.split_at(frames * points);
    let trajectory = Trajectory {
        points,
        grid: header.samples.grid,
        side: header.samples.side,
        times: header.times.clone(),
        positions: positions.to_vec(),
        final_vertices: final_vertices.to_vec(),
        adapt: Default::default(),
    };
    Ok((header, trajectory))
}

/// Checks that the counts of a `reference.bin` header agree with each other (the sample grid
/// with `settings.samples`), that its times and rest points are finite, its times increasing
/// and its floor errors not negative (`e_rms` and `e_final` always measured; a NaN tracked-point
/// error or Hausdorff distance is one that could not be); the reason otherwise.
fn check_header(h: &ReferenceHeader) -> Result<(), String> {
    let s = &h.samples;
    let n = h.settings.samples;
    if s.grid > s.rest.len() {
        return Err(format!(
            "{} grid samples of {} rest points",
            s.grid,
            s.rest.len()
        ));
    }
    if n.checked_mul(n).is_none_or(|nn| s.grid > nn) {
        return Err(format!(
            "{} grid samples, more than settings.samples = {n} squared",
            s.grid
        ));
    }
    if s.side != 0 && (s.side != n || s.side * s.side != s.grid) {
        return Err(format!(
            "a {0} x {0} sample grid of {1} points, with settings.samples = {n}",
            s.side, s.grid
        ));
    }
    if !s
        .rest
        .iter()
        .flatten()
        .chain(&h.times)
        .all(|x| x.is_finite())
    {
        return Err("a rest point or frame time is not finite".into());
    }
    // An edited header: the errors against it would be measured at the wrong times or over
    // nothing, and the floor would say nothing true.
    if h.times.is_empty() || h.times.windows(2).any(|w| w[0] >= w[1]) {
        return Err("the frame times are not one or more increasing times".into());
    }
    let f = &h.floor;
    let measured = [f.e_rms, f.e_final].iter().all(|e| e.is_finite());
    if !measured
        || [f.e_rms, f.e_final, f.tracked_err, f.hausdorff]
            .iter()
            .any(|e| *e < 0.0 || e.is_infinite())
    {
        return Err(
            "a floor error is negative or infinite, or its e_rms or e_final missing".into(),
        );
    }
    Ok(())
}
