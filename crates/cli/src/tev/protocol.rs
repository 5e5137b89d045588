//! The two packets of tev's IPC protocol that `render --tev` sends.
//!
//! Checked against tev's source (github.com/Tom94/tev):
//! `include/tev/Ipc.h` (the packet types and `IpcPacket::OStream`) and
//! `src/Ipc.cpp` (`IpcPacket::setCreateImage`, `IpcPacket::setUpdateImage`,
//! and `Ipc::SocketConnection::service`, which reads the length prefix).
//! A packet is its total length in bytes as a little-endian u32 — counting
//! those 4 bytes themselves — then the packet type as one byte, then the
//! fields: booleans one byte (0 or 1), integers little-endian, strings
//! UTF-8 ending in a NUL byte, pixel values 32-bit floats (little-endian).

/// `CreateImage`: a blank image of a size and a set of channel names
/// (an image of the same name is replaced).
pub const CREATE_IMAGE: u8 = 4;
/// `UpdateImageV3`: a rectangle of some channels' pixels, each channel
/// at its own offset and stride into the floats that follow.
pub const UPDATE_IMAGE_V3: u8 = 6;

/// A rectangle of pixels: left, top, width, height.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Rect {
    pub x: u32,
    pub y: u32,
    pub width: u32,
    pub height: u32,
}

/// A packet being written: the length is filled in by `finish`.
struct Packet(Vec<u8>);

impl Packet {
    fn new(kind: u8, capacity: usize) -> Self {
        let mut bytes = Vec::with_capacity(capacity + 5);
        bytes.extend_from_slice(&[0; 4]);
        bytes.push(kind);
        Self(bytes)
    }

    fn boolean(&mut self, v: bool) {
        self.0.push(u8::from(v));
    }

    fn i32(&mut self, v: u32) {
        // The protocol's sizes are signed 32-bit; ours are checked to fit.
        let v = i32::try_from(v).unwrap_or(i32::MAX);
        self.0.extend_from_slice(&v.to_le_bytes());
    }

    fn i64(&mut self, v: u64) {
        let v = i64::try_from(v).unwrap_or(i64::MAX);
        self.0.extend_from_slice(&v.to_le_bytes());
    }

    fn string(&mut self, s: &str) {
        // A NUL inside would end the string early on tev's side.
        self.0.extend(s.bytes().filter(|&b| b != 0));
        self.0.push(0);
    }

    fn finish(mut self) -> Vec<u8> {
        let n = u32::try_from(self.0.len()).unwrap_or(u32::MAX);
        self.0[..4].copy_from_slice(&n.to_le_bytes());
        self.0
    }
}

/// CreateImage: grab focus, image name, width, height, channel count,
/// channel names.
pub fn create_image(name: &str, width: u32, height: u32, channels: &[&str]) -> Vec<u8> {
    let mut p = Packet::new(CREATE_IMAGE, name.len() + 13 + 8 * channels.len());
    p.boolean(true);
    p.string(name);
    p.i32(width);
    p.i32(height);
    p.i32(channels.len() as u32);
    for c in channels {
        p.string(c);
    }
    p.finish()
}

/// UpdateImage v3: grab focus, image name, channel count, channel names,
/// x, y, width, height, one offset (i64) per channel, one stride (i64) per
/// channel, then the floats. `planes[c]` holds channel `c`'s pixels of
/// `rect`, row by row; they are sent one after another (offset
/// `c × pixels`, stride 1).
pub fn update_image(name: &str, channels: &[&str], rect: Rect, planes: &[&[f32]]) -> Vec<u8> {
    debug_assert_eq!(channels.len(), planes.len());
    let pixels = rect.width as usize * rect.height as usize;
    debug_assert!(planes.iter().all(|p| p.len() == pixels));
    let floats: usize = planes.iter().map(|p| p.len()).sum();
    let mut p = Packet::new(
        UPDATE_IMAGE_V3,
        name.len() + 22 + 24 * channels.len() + 4 * floats,
    );
    p.boolean(false);
    p.string(name);
    p.i32(channels.len() as u32);
    for c in channels {
        p.string(c);
    }
    for v in [rect.x, rect.y, rect.width, rect.height] {
        p.i32(v);
    }
    for c in 0..channels.len() {
        p.i64((c * pixels) as u64);
    }
    for _ in channels {
        p.i64(1);
    }
    for plane in planes {
        for v in *plane {
            p.0.extend_from_slice(&v.to_le_bytes());
        }
    }
    p.finish()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn create_image_bytes_by_hand() {
        let bytes = create_image("a", 2, 3, &["X", "V"]);
        #[rustfmt::skip]
        let expected: Vec<u8> = vec![
            24, 0, 0, 0,   // total length, these 4 bytes included
            4,             // CreateImage
            1,             // grab focus
            b'a', 0,       // name
            2, 0, 0, 0,    // width
            3, 0, 0, 0,    // height
            2, 0, 0, 0,    // channels
            b'X', 0, b'V', 0,
        ];
        assert_eq!(bytes, expected);
    }

    #[test]
    fn update_image_bytes_by_hand() {
        let rect = Rect {
            x: 1,
            y: 2,
            width: 1,
            height: 1,
        };
        let bytes = update_image("i", &["R", "G"], rect, &[&[1.0], &[-2.0]]);
        #[rustfmt::skip]
        let expected: Vec<u8> = vec![
            72, 0, 0, 0,   // total length
            6,             // UpdateImage v3
            0,             // grab focus
            b'i', 0,       // name
            2, 0, 0, 0,    // channels
            b'R', 0, b'G', 0,
            1, 0, 0, 0,    // x
            2, 0, 0, 0,    // y
            1, 0, 0, 0,    // width
            1, 0, 0, 0,    // height
            0, 0, 0, 0, 0, 0, 0, 0, // offset of R
            1, 0, 0, 0, 0, 0, 0, 0, // offset of G
            1, 0, 0, 0, 0, 0, 0, 0, // stride of R
            1, 0, 0, 0, 0, 0, 0, 0, // stride of G
            0x00, 0x00, 0x80, 0x3f, // 1.0
            0x00, 0x00, 0x00, 0xc0, // -2.0
        ];
        assert_eq!(bytes, expected);
    }

    #[test]
    fn a_nul_in_a_name_does_not_split_it() {
        let bytes = create_image("a\0b", 1, 1, &["Y"]);
        assert_eq!(&bytes[6..9], b"ab\0");
        assert_eq!(
            bytes.len() as u32,
            u32::from_le_bytes([bytes[0], bytes[1], bytes[2], bytes[3]])
        );
    }
}
