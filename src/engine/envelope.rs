//! The checkpoint envelope every engine seals its state in: it names the engine, versions the
//! payload and guards it with a length and a checksum.
//!
//! Layout (little endian): magic `GRANFLOW-<ENGINE>` zero-padded to 16 bytes (the engine's
//! registry name in capitals, at most 7 characters: `GRANFLOW-EDMD\0\0\0`), payload format
//! version (u32), payload length (u64), CRC-32 of the payload (u32), payload. A truncated,
//! corrupt, foreign or future-version file is rejected with a message saying which check
//! failed; it is never silently used. EDMD checkpoints written before the registry existed
//! have exactly this layout, so they still open (as EDMD).

use super::EngineError;

const PREFIX: &[u8] = b"GRANFLOW-";
const MAGIC_LEN: usize = 16;
/// Bytes before the payload.
pub const HEADER_LEN: usize = MAGIC_LEN + 4 + 8 + 4;

/// An opened envelope: which engine wrote it, the payload's format version and the payload.
#[derive(Debug, PartialEq)]
pub struct Sealed<'a> {
    /// the engine's registry name (lower case)
    pub engine: String,
    pub version: u32,
    pub payload: &'a [u8],
}

fn magic(engine: &str) -> [u8; MAGIC_LEN] {
    let name = engine.to_ascii_uppercase();
    assert!(
        PREFIX.len() + name.len() <= MAGIC_LEN && name.bytes().all(|b| b.is_ascii_alphanumeric()),
        "engine name `{engine}` does not fit a checkpoint magic"
    );
    let mut out = [0u8; MAGIC_LEN];
    out[..PREFIX.len()].copy_from_slice(PREFIX);
    out[PREFIX.len()..PREFIX.len() + name.len()].copy_from_slice(name.as_bytes());
    out
}

/// Seal a payload of `engine` (its registry name) at format `version`.
pub fn seal(engine: &str, version: u32, payload: &[u8]) -> Vec<u8> {
    let mut out = Vec::with_capacity(HEADER_LEN + payload.len());
    out.extend_from_slice(&magic(engine));
    out.extend_from_slice(&version.to_le_bytes());
    out.extend_from_slice(&(payload.len() as u64).to_le_bytes());
    out.extend_from_slice(&crc32fast::hash(payload).to_le_bytes());
    out.extend_from_slice(payload);
    out
}

/// Seal the postcard bytes of `value` as [`seal`] seals a payload (the same bytes), serialised
/// straight into the envelope: one buffer of the exact size, where `seal(postcard::to_stdvec)`
/// holds the payload twice and the first with growth slack (a big engine state's checkpoint
/// is the peak of a job's memory).
pub fn seal_value<T: serde::Serialize>(engine: &str, version: u32, value: &T) -> Vec<u8> {
    let len = postcard::experimental::serialized_size(value).expect("the state serialises");
    let mut out = Vec::with_capacity(HEADER_LEN + len);
    out.extend_from_slice(&magic(engine));
    out.extend_from_slice(&version.to_le_bytes());
    out.extend_from_slice(&(len as u64).to_le_bytes());
    out.extend_from_slice(&[0; 4]);
    let mut out = postcard::to_extend(value, out).expect("the state serialises");
    assert_eq!(
        out.len(),
        HEADER_LEN + len,
        "postcard's size and bytes agree"
    );
    let crc = crc32fast::hash(&out[HEADER_LEN..]);
    out[HEADER_LEN - 4..HEADER_LEN].copy_from_slice(&crc.to_le_bytes());
    out
}

/// Check the envelope and return its engine, version and payload.
pub fn open(bytes: &[u8]) -> Result<Sealed<'_>, EngineError> {
    let fail = |why: String| Err(EngineError::Checkpoint(why));
    if bytes.len() < HEADER_LEN {
        return fail(format!(
            "file is {} bytes, shorter than the {HEADER_LEN}-byte header (truncated)",
            bytes.len()
        ));
    }
    let name_bytes = &bytes[PREFIX.len()..MAGIC_LEN];
    let end = name_bytes
        .iter()
        .position(|&b| b == 0)
        .unwrap_or(name_bytes.len());
    let name = &name_bytes[..end];
    if &bytes[..PREFIX.len()] != PREFIX
        || name.is_empty()
        || !name.iter().all(|b| b.is_ascii_alphanumeric())
        || name_bytes[end..].iter().any(|&b| b != 0)
    {
        return fail("not a granflow checkpoint (wrong magic bytes)".into());
    }
    let version = u32::from_le_bytes(bytes[16..20].try_into().expect("4 bytes"));
    let len = u64::from_le_bytes(bytes[20..28].try_into().expect("8 bytes"));
    let crc = u32::from_le_bytes(bytes[28..32].try_into().expect("4 bytes"));
    let payload = &bytes[HEADER_LEN..];
    if payload.len() as u64 != len {
        return fail(format!(
            "payload is {} bytes, header says {len} (truncated or padded)",
            payload.len()
        ));
    }
    if crc32fast::hash(payload) != crc {
        return fail("checksum mismatch (corrupt file)".into());
    }
    Ok(Sealed {
        engine: String::from_utf8_lossy(name).to_ascii_lowercase(),
        version,
        payload,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trip_names_the_engine() {
        let bytes = seal("lga", 3, b"state");
        assert_eq!(&bytes[..16], b"GRANFLOW-LGA\0\0\0\0");
        let s = open(&bytes).unwrap();
        assert_eq!(
            (s.engine.as_str(), s.version, s.payload),
            ("lga", 3, &b"state"[..])
        );
    }

    #[test]
    fn a_sealed_value_is_its_sealed_postcard_bytes() {
        let value = (
            vec![[1.5f64, -2.0, 3.25]; 300],
            "rest",
            7u64,
            vec![0u8; 129],
        );
        let expected = seal("dsmc", 4, &postcard::to_stdvec(&value).unwrap());
        let bytes = seal_value("dsmc", 4, &value);
        assert_eq!(bytes, expected);
        assert_eq!(bytes.capacity(), bytes.len(), "one exact buffer");
    }

    #[test]
    fn edmd_magic_is_the_pre_registry_one() {
        assert_eq!(&magic("edmd"), b"GRANFLOW-EDMD\0\0\0");
    }

    #[test]
    fn damage_is_rejected() {
        let bytes = seal("edmd", 1, b"0123456789");
        assert!(open(&bytes[..bytes.len() - 1]).is_err(), "truncated");
        let mut flipped = bytes.clone();
        *flipped.last_mut().unwrap() ^= 1;
        assert!(open(&flipped).is_err(), "corrupt");
        let mut foreign = bytes.clone();
        foreign[0] = b'X';
        assert!(open(&foreign).is_err(), "foreign");
        assert!(open(&bytes[..10]).is_err(), "short");
    }
}
