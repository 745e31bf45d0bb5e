//! MAVLink 2 framing of datagrams, with optional message signing.
//!
//! The SITL owns its sockets (it must answer whoever spoke last, add latency
//! and drop packets), so it frames messages itself with rust-mavlink's raw
//! frame types rather than going through a `MavConnection`.

use mavlink::dialects::common::MavMessage;
use mavlink::{MAV_STX_V2, MAVLinkV2MessageRaw, MavHeader, MavlinkVersion, Message};
use mavlink::{SigningConfig, SigningData};

/// Signing state of one link: the key plus replay-protection timestamps.
pub struct Signing {
    data: SigningData,
}

impl Signing {
    /// Signing with `key`: outgoing messages are signed and unsigned input is refused.
    pub fn new(key: [u8; 32]) -> Self {
        Self {
            data: SigningData::from_config(SigningConfig::new(key, 0, true, false)),
        }
    }
}

/// Why a frame in a datagram was not delivered.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Rejection {
    /// Signing is on and the frame was unsigned, wrongly signed or replayed.
    BadSignature,
    /// The CRC and framing were fine but the payload is not a common-dialect
    /// message we can decode (unknown id or out-of-range enum).
    Undecodable {
        /// Message id of the frame.
        message_id: u32,
    },
}

/// Outcome of decoding one datagram.
#[derive(Debug, Default)]
pub struct Decoded {
    /// Messages that passed framing, CRC and signature checks.
    pub messages: Vec<(MavHeader, MavMessage)>,
    /// Frames that were framed correctly but refused.
    pub rejected: Vec<Rejection>,
}

/// Splits a datagram into MAVLink 2 messages. Garbage, MAVLink 1 frames and
/// truncated frames are skipped; this never panics on any input.
///
/// Datagrams are scanned directly rather than through `MavlinkReader`,
/// because a stream reader waits for the rest of a truncated frame, which in
/// a datagram would swallow every valid frame after it.
pub fn decode(datagram: &[u8], signing: Option<&Signing>) -> Decoded {
    let mut out = Decoded::default();
    let mut start = 0;
    while let Some(offset) = datagram
        .get(start..)
        .and_then(|rest| rest.iter().position(|b| *b == MAV_STX_V2))
    {
        let at = start + offset;
        match frame_at(&datagram[at..]) {
            Some(raw) => {
                start = at + raw.raw_bytes().len();
                accept(raw, signing, &mut out);
            }
            None => start = at + 1,
        }
    }
    out
}

/// The only incompatibility flag MAVLink 2 defines: the frame is signed.
const IFLAG_SIGNED: u8 = 0x01;

/// A CRC-valid MAVLink 2 frame starting at the first byte of `bytes`, if any.
///
/// A frame with an incompatibility flag other than "signed" is not one we
/// understand, and the MAVLink 2 rule is to drop it, as PX4 and ArduPilot
/// do. That includes rust-mavlink's non-standard 32-bit system id flag
/// (0x02), which changes the header layout.
fn frame_at(bytes: &[u8]) -> Option<MAVLinkV2MessageRaw> {
    const MIN_FRAME_BYTES: usize = 12; // STX + 9 header bytes + 2 CRC bytes
    if bytes.len() < MIN_FRAME_BYTES || bytes[2] & !IFLAG_SIGNED != 0 {
        return None;
    }
    let mut raw = MAVLinkV2MessageRaw::new();
    let buffer = raw.as_mut_slice();
    let len = bytes.len().min(buffer.len());
    buffer[..len].copy_from_slice(&bytes[..len]);
    // raw_bytes() derives the frame length from the header fields.
    let frame_len = raw.raw_bytes().len();
    (frame_len <= bytes.len() && raw.has_valid_crc::<MavMessage>()).then_some(raw)
}

/// Checks the signature and decodes one frame into `out`.
fn accept(raw: MAVLinkV2MessageRaw, signing: Option<&Signing>, out: &mut Decoded) {
    if let Some(signing) = signing
        && !signing.data.verify_signature(&raw)
    {
        out.rejected.push(Rejection::BadSignature);
        return;
    }
    let header = MavHeader {
        system_id: raw.system_id(),
        component_id: raw.component_id(),
        sequence: raw.sequence(),
    };
    match MavMessage::parse(MavlinkVersion::V2, raw.message_id(), raw.payload()) {
        Ok(message) => out.messages.push((header, message)),
        Err(_) => out.rejected.push(Rejection::Undecodable {
            message_id: raw.message_id(),
        }),
    }
}

/// Frames `message` as MAVLink 2 from `header`, signed when `signing` is set.
pub fn encode(header: MavHeader, message: &MavMessage, signing: Option<&Signing>) -> Vec<u8> {
    let mut raw = MAVLinkV2MessageRaw::new();
    match signing {
        Some(signing) => {
            raw.serialize_message_for_signing(header, message);
            signing.data.sign_message(&mut raw);
        }
        None => raw.serialize_message(header, message),
    }
    raw.raw_bytes().to_vec()
}

#[cfg(test)]
mod tests {
    use super::*;
    use mavlink::dialects::common::{HEARTBEAT_DATA, MavAutopilot, MavModeFlag, MavState, MavType};

    fn heartbeat() -> MavMessage {
        MavMessage::HEARTBEAT(HEARTBEAT_DATA {
            custom_mode: 7,
            mavtype: MavType::MAV_TYPE_GCS,
            autopilot: MavAutopilot::MAV_AUTOPILOT_INVALID,
            base_mode: MavModeFlag::empty(),
            system_status: MavState::MAV_STATE_ACTIVE,
            mavlink_version: 3,
        })
    }

    fn header() -> MavHeader {
        MavHeader {
            system_id: 255,
            component_id: 190,
            sequence: 4,
        }
    }

    #[test]
    fn round_trip_with_garbage_around() {
        let mut datagram = vec![0xfd, 1, 2, 3, 0xfe, 9];
        datagram.extend(encode(header(), &heartbeat(), None));
        datagram.extend([0xfd, 0xfd, 0]);
        datagram.extend(encode(header(), &heartbeat(), None));
        let decoded = decode(&datagram, None);
        assert_eq!(decoded.messages.len(), 2);
        assert_eq!(decoded.messages[0].0, header());
        assert_eq!(decoded.messages[0].1, heartbeat());
    }

    #[test]
    fn signing_rejects_unsigned_and_wrong_keys() {
        let ours = Signing::new([7; 32]);
        let theirs = Signing::new([8; 32]);
        assert_eq!(
            decode(&encode(header(), &heartbeat(), None), Some(&ours)).rejected,
            vec![Rejection::BadSignature]
        );
        assert_eq!(
            decode(&encode(header(), &heartbeat(), Some(&theirs)), Some(&ours)).rejected,
            vec![Rejection::BadSignature]
        );
        let sender = Signing::new([7; 32]);
        let good = decode(&encode(header(), &heartbeat(), Some(&sender)), Some(&ours));
        assert_eq!(good.messages.len(), 1);
    }

    #[test]
    fn replayed_signed_frames_are_rejected() {
        let ours = Signing::new([7; 32]);
        let sender = Signing::new([7; 32]);
        let frame = encode(header(), &heartbeat(), Some(&sender));
        assert_eq!(decode(&frame, Some(&ours)).messages.len(), 1);
        assert_eq!(
            decode(&frame, Some(&ours)).rejected,
            vec![Rejection::BadSignature]
        );
    }

    #[test]
    fn arbitrary_bytes_never_panic() {
        let mut state = 0x1234_5678_u32;
        for len in 0..400 {
            let bytes: Vec<u8> = (0..len)
                .map(|i| {
                    state = state.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
                    if i % 17 == 0 {
                        0xfd
                    } else {
                        (state >> 24) as u8
                    }
                })
                .collect();
            let _ = decode(&bytes, None);
            let _ = decode(&bytes, Some(&Signing::new([1; 32])));
        }
    }
}
