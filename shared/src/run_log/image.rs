//! The log image: the 32-byte header and the records behind it (layout:
//! the tables in `run_log`'s module doc). What the robot answers to `LOG`
//! and what a saved log file holds. [`decode`] is total: any bytes give a
//! [`LogImage`] or a [`DecodeError`] saying what is wrong, never a panic.

use super::power_up::ThisRun;
use super::record::{Record, RecordError, RECORD_LEN};
use crc::{Crc, Digest, NoTable, CRC_32_ISO_HDLC};

/// Bytes of the header.
pub const HEADER_LEN: usize = 32;
pub const MAGIC: [u8; 4] = *b"SWLG";
/// The version written. Version 2 has version 1's layout; only the
/// dropped count's meaning changed: always this power-up's, also when the
/// records are an earlier power-up's (`power_up`). A version-1 reader
/// refuses it rather than read a lost run as none.
pub const VERSION: u16 = 2;
/// The oldest version [`decode`] reads (saved files).
pub const OLDEST_VERSION: u16 = 1;
/// Header bytes the CRC covers (everything before the CRC itself).
const CRC_AT: usize = 28;
const UNPAIRED: u16 = 0xFFFF;

/// Bitwise, without the 1 KiB table: flash is the scarcer resource (the
/// firmware's budget is 32 KiB with the USB stack); a 10-minute log's
/// 96 kB then take some 50 ms of the chip's time at a readout, with the
/// watchdog fed between pieces (`LogStore::readout`).
const CRC32: Crc<u32, NoTable> = Crc::<u32, NoTable>::new(&CRC_32_ISO_HDLC);

/// Header flag: the motor was off when the image was made.
pub const FLAG_CLOSED: u16 = 1 << 0;
/// Header flag: the log of an earlier power-up, its header rebuilt from
/// the records in flash (dropped count unknown, foreign frames summed).
pub const FLAG_RECOVERED: u16 = 1 << 1;

/// The header's fields (the magic, version, lengths and CRC are implied).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Header {
    pub sample_period_ms: u16,
    pub record_count: u32,
    /// Records this power-up took but did not keep (log slot full or not
    /// yet erased), whatever power-up's records the image holds.
    pub dropped_records: u32,
    /// Frames from other remotes ignored since power-up.
    pub foreign_frames: u32,
    /// The paired remote's NEC address, if paired.
    pub paired_address: Option<u8>,
    pub flags: u16,
}

impl Header {
    /// The header's 32 bytes, with `crc` as computed by [`ImageDigest`].
    pub fn to_bytes(&self, crc: u32) -> [u8; HEADER_LEN] {
        let mut b = self.fields();
        b[CRC_AT..].copy_from_slice(&crc.to_le_bytes());
        b
    }

    fn fields(&self) -> [u8; HEADER_LEN] {
        let mut b = [0u8; HEADER_LEN];
        b[0..4].copy_from_slice(&MAGIC);
        b[4..6].copy_from_slice(&VERSION.to_le_bytes());
        b[6..8].copy_from_slice(&(HEADER_LEN as u16).to_le_bytes());
        b[8..10].copy_from_slice(&(RECORD_LEN as u16).to_le_bytes());
        b[10..12].copy_from_slice(&self.sample_period_ms.to_le_bytes());
        b[12..16].copy_from_slice(&self.record_count.to_le_bytes());
        b[16..20].copy_from_slice(&self.dropped_records.to_le_bytes());
        b[20..24].copy_from_slice(&self.foreign_frames.to_le_bytes());
        let addr = self.paired_address.map_or(UNPAIRED, u16::from);
        b[24..26].copy_from_slice(&addr.to_le_bytes());
        b[26..28].copy_from_slice(&self.flags.to_le_bytes());
        b
    }

    /// Bytes needed for the whole image.
    pub fn image_len(&self) -> usize {
        HEADER_LEN.saturating_add((self.record_count as usize).saturating_mul(RECORD_LEN))
    }
}

/// The image's CRC, fed the records in order (the firmware streams them
/// from flash): header bytes 0-27 first, then every record's bytes.
pub struct ImageDigest {
    digest: Digest<'static, u32, NoTable>,
}

impl ImageDigest {
    pub fn new(header: &Header) -> Self {
        let mut digest = CRC32.digest();
        digest.update(&header.fields()[..CRC_AT]);
        Self { digest }
    }

    pub fn update(&mut self, record_bytes: &[u8]) {
        self.digest.update(record_bytes);
    }

    pub fn finalize(self) -> u32 {
        self.digest.finalize()
    }
}

/// Why [`encode`] wrote nothing.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EncodeError {
    /// The output buffer holds fewer bytes than the image needs.
    BufferTooSmall { needed: usize, got: usize },
    /// More records than the header's 32-bit count can say.
    TooManyRecords,
}

/// Write the image of `records` under `header` (its `record_count` is
/// replaced by `records.len()`) into `out`; the image's length.
pub fn encode(header: &Header, records: &[Record], out: &mut [u8]) -> Result<usize, EncodeError> {
    let count = u32::try_from(records.len()).map_err(|_| EncodeError::TooManyRecords)?;
    let header = Header {
        record_count: count,
        ..*header
    };
    let needed = header.image_len();
    if out.len() < needed {
        return Err(EncodeError::BufferTooSmall {
            needed,
            got: out.len(),
        });
    }
    let mut digest = ImageDigest::new(&header);
    for (r, chunk) in records
        .iter()
        .zip(out[HEADER_LEN..].chunks_exact_mut(RECORD_LEN))
    {
        chunk.copy_from_slice(&r.to_bytes());
        digest.update(chunk);
    }
    out[..HEADER_LEN].copy_from_slice(&header.to_bytes(digest.finalize()));
    Ok(needed)
}

/// What is wrong with bytes that are not a log image.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DecodeError {
    /// Fewer bytes than a header.
    TooShort { len: usize },
    /// The first four bytes are not `SWLG`: not a swimbot log.
    BadMagic([u8; 4]),
    /// A log format this code does not read.
    UnsupportedVersion(u16),
    /// The header's lengths are not this version's (32 and 16).
    BadLengths { header_len: u16, record_len: u16 },
    /// A zero sample period.
    ZeroPeriod,
    /// The paired address is neither 0-255 nor unpaired (0xFFFF).
    BadAddress(u16),
    /// The header promises more records than the bytes hold.
    Truncated { expected: usize, got: usize },
    /// Bytes after the last record.
    TrailingBytes { expected: usize, got: usize },
    /// The CRC does not match: the image was damaged.
    Crc { stored: u32, computed: u32 },
    /// Record `index` is malformed.
    Record { index: u32, error: RecordError },
}

/// A decoded image: the header and its records (already checked).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LogImage<'a> {
    pub header: Header,
    /// The format version it was written in ([`OLDEST_VERSION`]..=[`VERSION`]).
    pub version: u16,
    /// The records' bytes, `RECORD_LEN` each.
    bytes: &'a [u8],
}

impl<'a> LogImage<'a> {
    pub fn len(&self) -> usize {
        self.bytes.len() / RECORD_LEN
    }

    pub fn is_empty(&self) -> bool {
        self.bytes.is_empty()
    }

    /// What became of the run of the power-up that made the image
    /// (`None`: a version-1 image of an earlier power-up's log cannot say).
    pub fn this_run(&self) -> Option<ThisRun> {
        ThisRun::of(&self.header, self.version)
    }

    /// The records in order (each was checked by [`decode`]).
    pub fn records(&self) -> impl Iterator<Item = Record> + 'a {
        self.bytes
            .chunks_exact(RECORD_LEN)
            .filter_map(|c| c.try_into().ok().and_then(|b| Record::from_bytes(b).ok()))
    }
}

fn u16_at(b: &[u8], i: usize) -> u16 {
    u16::from_le_bytes([b[i], b[i + 1]])
}

fn u32_at(b: &[u8], i: usize) -> u32 {
    u32::from_le_bytes([b[i], b[i + 1], b[i + 2], b[i + 3]])
}

/// The header's fields and stored CRC, checked for form only.
pub(crate) fn decode_header(b: &[u8]) -> Result<(Header, u32), DecodeError> {
    if b.len() < HEADER_LEN {
        return Err(DecodeError::TooShort { len: b.len() });
    }
    let magic = [b[0], b[1], b[2], b[3]];
    if magic != MAGIC {
        return Err(DecodeError::BadMagic(magic));
    }
    let version = u16_at(b, 4);
    if !(OLDEST_VERSION..=VERSION).contains(&version) {
        return Err(DecodeError::UnsupportedVersion(version));
    }
    let (header_len, record_len) = (u16_at(b, 6), u16_at(b, 8));
    if usize::from(header_len) != HEADER_LEN || usize::from(record_len) != RECORD_LEN {
        return Err(DecodeError::BadLengths {
            header_len,
            record_len,
        });
    }
    let sample_period_ms = u16_at(b, 10);
    if sample_period_ms == 0 {
        return Err(DecodeError::ZeroPeriod);
    }
    let addr = u16_at(b, 24);
    let paired_address = match addr {
        UNPAIRED => None,
        a => Some(u8::try_from(a).map_err(|_| DecodeError::BadAddress(a))?),
    };
    let header = Header {
        sample_period_ms,
        record_count: u32_at(b, 12),
        dropped_records: u32_at(b, 16),
        foreign_frames: u32_at(b, 20),
        paired_address,
        flags: u16_at(b, 26),
    };
    Ok((header, u32_at(b, CRC_AT)))
}

/// Read a log image: any bytes give the log or what is wrong with them.
pub fn decode(bytes: &[u8]) -> Result<LogImage<'_>, DecodeError> {
    let (header, stored) = decode_header(bytes)?;
    let expected = header.image_len();
    if bytes.len() < expected {
        return Err(DecodeError::Truncated {
            expected,
            got: bytes.len(),
        });
    }
    if bytes.len() > expected {
        return Err(DecodeError::TrailingBytes {
            expected,
            got: bytes.len(),
        });
    }
    let records = &bytes[HEADER_LEN..];
    // Over the bytes as they are (a version-1 file's own version field).
    let mut digest = CRC32.digest();
    digest.update(&bytes[..CRC_AT]);
    digest.update(records);
    let computed = digest.finalize();
    if computed != stored {
        return Err(DecodeError::Crc { stored, computed });
    }
    for (i, chunk) in records.chunks_exact(RECORD_LEN).enumerate() {
        let b: &[u8; RECORD_LEN] = chunk
            .try_into()
            .map_err(|_| DecodeError::TooShort { len: chunk.len() })?;
        Record::from_bytes(b).map_err(|error| DecodeError::Record {
            index: i as u32,
            error,
        })?;
    }
    Ok(LogImage {
        header,
        version: u16_at(bytes, 4),
        bytes: records,
    })
}
