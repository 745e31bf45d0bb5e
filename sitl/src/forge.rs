//! Hand-built MAVLink 2 frames with valid CRCs, for fuzzers and robustness tests.
//!
//! A fuzzer that flips random bytes almost never gets past the CRC check, so
//! it only ever exercises the framing layer. These helpers take arbitrary
//! parts — any message id, any payload bytes, any header — and produce a
//! frame whose checksum (and, optionally, signature) is correct, so the bytes
//! reach the message parser and the code that acts on the message.
//!
//! The CRC uses the message's CRC_EXTRA from the common dialect
//! ([`crc_extra`]); ids outside the dialect get CRC_EXTRA 0, which is what
//! rust-mavlink checks them against, so the frame is still well formed and
//! gets as far as "unknown message". The checksum itself is rust-mavlink's
//! [`mavlink::calculate_crc`] (CRC-16/MCRF4XX from the `crc-any` crate).
//!
//! ```
//! use mavlink::dialects::common::{MavMessage, HEARTBEAT_DATA};
//! use swarmctl_sitl::forge;
//! // A heartbeat payload with random bytes, framed with a valid CRC:
//! let bytes = forge::frame(255, 190, 0, 0, &[1, 2, 3, 4, 5, 6, 7, 8, 9]);
//! assert_eq!(bytes[0], 0xfd);
//! // A real message, encoded and framed:
//! let heartbeat = MavMessage::HEARTBEAT(HEARTBEAT_DATA::default());
//! let bytes = forge::message(255, 190, 7, &heartbeat);
//! assert!(forge::known_message_ids().contains(&0));
//! # let _ = bytes;
//! ```

use mavlink::dialects::common::MavMessage;
use mavlink::{MAV_STX_V2, MAVLinkV2MessageRaw, MavlinkVersion, Message};

/// Largest MAVLink 2 payload; longer payloads are cut to this.
pub const MAX_PAYLOAD_LEN: usize = 255;

/// Incompatibility flag: the frame carries a 13-byte signature.
pub const IFLAG_SIGNED: u8 = 0x01;

/// Bytes of the MAVLink 2 header after the start byte (no 32-bit system id).
const HEADER_LEN: usize = 9;

/// Bytes of the signature trailer: link id, 48-bit timestamp, 48-bit signature.
const SIGNATURE_LEN: usize = 13;

/// Every message id of the common dialect, for strategies that want real ids.
pub fn known_message_ids() -> &'static [u32] {
    MavMessage::all_ids()
}

/// CRC_EXTRA of `message_id` in the common dialect (0 for unknown ids).
pub fn crc_extra(message_id: u32) -> u8 {
    MavMessage::extra_crc(message_id)
}

/// The parts of one MAVLink 2 frame. Every combination is framed with a
/// valid CRC; the payload is used as given (no zero trimming), cut to 255
/// bytes, and the message id to 24 bits.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Frame {
    /// Sender system id.
    pub system_id: u8,
    /// Sender component id.
    pub component_id: u8,
    /// Packet sequence number.
    pub sequence: u8,
    /// Message id (24 bits on the wire).
    pub message_id: u32,
    /// Payload bytes as they go on the wire.
    pub payload: Vec<u8>,
    /// Incompatibility flags. [`IFLAG_SIGNED`] is set by [`Frame::signed`];
    /// set other bits only to test how a receiver handles unknown flags
    /// (bit 0x02 is rust-mavlink's 32-bit system id extension and changes
    /// the header layout, so it is cleared here).
    pub incompat_flags: u8,
    /// Compatibility flags (receivers must ignore unknown ones).
    pub compat_flags: u8,
}

/// A signature to attach to a frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Signature {
    /// The 32-byte secret key.
    pub key: [u8; 32],
    /// Link id of the signing stream.
    pub link_id: u8,
    /// 48-bit timestamp in units of 10 µs since 2015-01-01 (higher bits are dropped).
    /// Receivers refuse a timestamp not newer than the last one of the same
    /// stream, and a first one more than a minute old.
    pub timestamp: u64,
}

impl Signature {
    /// A signature with `key`, link 0 and the current time as timestamp,
    /// which a receiver with the same key accepts once per stream.
    pub fn now(key: [u8; 32]) -> Self {
        Self {
            key,
            link_id: 0,
            timestamp: current_timestamp(),
        }
    }
}

/// Current MAVLink signing timestamp: 10 µs units since 2015-01-01 00:00 UTC.
pub fn current_timestamp() -> u64 {
    const EPOCH_2015_S: u64 = 1_420_070_400;
    let since_unix = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .unwrap_or_default();
    let micros = since_unix
        .as_micros()
        .saturating_sub(u128::from(EPOCH_2015_S) * 1_000_000);
    u64::try_from(micros / 10).unwrap_or(u64::MAX)
}

impl Frame {
    /// A frame with no flags set.
    pub fn new(
        system_id: u8,
        component_id: u8,
        sequence: u8,
        message_id: u32,
        payload: &[u8],
    ) -> Self {
        Self {
            system_id,
            component_id,
            sequence,
            message_id,
            payload: payload.to_vec(),
            incompat_flags: 0,
            compat_flags: 0,
        }
    }

    /// The frame of an encoded `message` (payload trimmed of trailing zeros,
    /// as MAVLink 2 senders do).
    pub fn of_message(system_id: u8, component_id: u8, sequence: u8, message: &MavMessage) -> Self {
        let mut payload = [0u8; MAX_PAYLOAD_LEN];
        let len = message.ser(MavlinkVersion::V2, &mut payload);
        Self::new(
            system_id,
            component_id,
            sequence,
            message.message_id(),
            &payload[..len],
        )
    }

    fn payload_len(&self) -> usize {
        self.payload.len().min(MAX_PAYLOAD_LEN)
    }

    /// Header bytes after the start byte, with `incompat_flags` as given.
    fn header(&self, incompat_flags: u8) -> [u8; HEADER_LEN] {
        let id = (self.message_id & 0x00ff_ffff).to_le_bytes();
        [
            self.payload_len() as u8,
            incompat_flags & !0x02,
            self.compat_flags,
            self.sequence,
            self.system_id,
            self.component_id,
            id[0],
            id[1],
            id[2],
        ]
    }

    /// Start byte, header, payload and CRC.
    fn unsigned_bytes(&self, incompat_flags: u8) -> Vec<u8> {
        let header = self.header(incompat_flags);
        let payload = &self.payload[..self.payload_len()];
        let mut bytes = Vec::with_capacity(1 + HEADER_LEN + payload.len() + 2 + SIGNATURE_LEN);
        bytes.push(MAV_STX_V2);
        bytes.extend_from_slice(&header);
        bytes.extend_from_slice(payload);
        let crc = mavlink::calculate_crc(&bytes[1..], crc_extra(self.message_id));
        bytes.extend_from_slice(&crc.to_le_bytes());
        bytes
    }

    /// The frame's bytes with a valid CRC. If `incompat_flags` has
    /// [`IFLAG_SIGNED`] set, a 13-byte all-zero signature is appended so the
    /// frame length matches its header (a wrongly signed frame).
    pub fn to_bytes(&self) -> Vec<u8> {
        let mut bytes = self.unsigned_bytes(self.incompat_flags);
        if self.incompat_flags & IFLAG_SIGNED != 0 {
            bytes.extend_from_slice(&[0; SIGNATURE_LEN]);
        }
        bytes
    }

    /// The frame's bytes signed with `signature` (sets [`IFLAG_SIGNED`]).
    pub fn signed(&self, signature: &Signature) -> Vec<u8> {
        let mut bytes = self.unsigned_bytes(self.incompat_flags | IFLAG_SIGNED);
        bytes.push(signature.link_id);
        bytes.extend_from_slice(&signature.timestamp.to_le_bytes()[..6]);
        bytes.extend_from_slice(&[0; 6]);
        let mut raw = MAVLinkV2MessageRaw::new();
        raw.as_mut_slice()[..bytes.len()].copy_from_slice(&bytes);
        let mut value = [0u8; 6];
        raw.calculate_signature(&signature.key, &mut value);
        let end = bytes.len();
        bytes[end - 6..].copy_from_slice(&value);
        bytes
    }
}

/// An unsigned MAVLink 2 frame with a valid CRC from arbitrary parts.
/// Unknown message ids get CRC_EXTRA 0; payloads longer than 255 bytes are cut.
pub fn frame(
    system_id: u8,
    component_id: u8,
    sequence: u8,
    message_id: u32,
    payload: &[u8],
) -> Vec<u8> {
    Frame::new(system_id, component_id, sequence, message_id, payload).to_bytes()
}

/// Like [`frame`], signed with `signature`.
pub fn signed_frame(
    system_id: u8,
    component_id: u8,
    sequence: u8,
    message_id: u32,
    payload: &[u8],
    signature: &Signature,
) -> Vec<u8> {
    Frame::new(system_id, component_id, sequence, message_id, payload).signed(signature)
}

/// An encoded `message`, framed unsigned.
pub fn message(system_id: u8, component_id: u8, sequence: u8, message: &MavMessage) -> Vec<u8> {
    Frame::of_message(system_id, component_id, sequence, message).to_bytes()
}

/// An encoded `message`, framed and signed.
pub fn signed_message(
    system_id: u8,
    component_id: u8,
    sequence: u8,
    message: &MavMessage,
    signature: &Signature,
) -> Vec<u8> {
    Frame::of_message(system_id, component_id, sequence, message).signed(signature)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::codec;
    use mavlink::dialects::common::{
        COMMAND_LONG_DATA, HEARTBEAT_DATA, MavAutopilot, MavCmd, MavModeFlag, MavState, MavType,
        SET_POSITION_TARGET_LOCAL_NED_DATA,
    };
    use mavlink::{MavHeader, MavlinkReader, SigningConfig, SigningData};

    fn samples() -> Vec<MavMessage> {
        vec![
            MavMessage::HEARTBEAT(HEARTBEAT_DATA {
                custom_mode: 0x0604_0000,
                mavtype: MavType::MAV_TYPE_GCS,
                base_mode: MavModeFlag::MAV_MODE_FLAG_CUSTOM_MODE_ENABLED,
                system_status: MavState::MAV_STATE_ACTIVE,
                mavlink_version: 3,
                ..HEARTBEAT_DATA::default()
            }),
            MavMessage::COMMAND_LONG(COMMAND_LONG_DATA {
                target_system: 1,
                target_component: 1,
                command: MavCmd::MAV_CMD_COMPONENT_ARM_DISARM,
                param1: 1.0,
                ..COMMAND_LONG_DATA::default()
            }),
            MavMessage::SET_POSITION_TARGET_LOCAL_NED(SET_POSITION_TARGET_LOCAL_NED_DATA {
                x: 1.5,
                y: -2.0,
                z: -3.0,
                target_system: 1,
                target_component: 1,
                ..SET_POSITION_TARGET_LOCAL_NED_DATA::default()
            }),
            MavMessage::default_message_from_id(0).expect("heartbeat exists"),
        ]
    }

    fn read(bytes: &[u8], signing: Option<&SigningData>) -> Option<(MavHeader, MavMessage)> {
        let mut reader = MavlinkReader::new(bytes);
        reader
            .read_message_signed::<MavMessage>(MavlinkVersion::V2, signing)
            .ok()
    }

    #[test]
    fn forged_frames_of_real_messages_decode_with_rust_mavlink() {
        for (i, original) in samples().into_iter().enumerate() {
            let sequence = i as u8 * 3;
            let bytes = message(42, 190, sequence, &original);
            let (header, decoded) = read(&bytes, None).expect("rust-mavlink reads it");
            assert_eq!(decoded, original);
            assert_eq!(
                (header.system_id, header.component_id, header.sequence),
                (42, 190, sequence)
            );
            // Byte-identical to rust-mavlink's own serialisation.
            let theirs = codec::encode(
                MavHeader {
                    system_id: 42,
                    component_id: 190,
                    sequence,
                },
                &original,
                None,
            );
            assert_eq!(bytes, theirs);
            assert_eq!(codec::decode(&bytes, None).messages.len(), 1);
        }
    }

    #[test]
    fn untrimmed_payloads_still_decode() {
        // The full 33-byte COMMAND_LONG payload, trailing zeros kept.
        let command = &samples()[1];
        let mut payload = [0u8; MAX_PAYLOAD_LEN];
        let trimmed = command.ser(MavlinkVersion::V2, &mut payload);
        assert!(trimmed <= 33);
        let bytes = frame(9, 1, 0, command.message_id(), &payload[..33]);
        assert_eq!(read(&bytes, None).map(|(_, m)| m).as_ref(), Some(command));
    }

    #[test]
    fn every_known_id_gets_a_valid_crc() {
        assert!(known_message_ids().len() > 200);
        for &id in known_message_ids() {
            let bytes = frame(1, 1, 0, id, &[0xa5; 7]);
            let mut raw = MAVLinkV2MessageRaw::new();
            raw.as_mut_slice()[..bytes.len()].copy_from_slice(&bytes);
            assert!(raw.has_valid_crc::<MavMessage>(), "id {id}");
            assert_eq!(raw.raw_bytes().len(), bytes.len());
        }
    }

    #[test]
    fn unknown_ids_and_odd_parts_are_well_formed() {
        for (id, len) in [(0x00ff_ffff, 0), (77_777, 300), (1_000_000, 255)] {
            let bytes = frame(3, 4, 5, id, &vec![0xfd; len]);
            assert_eq!(bytes.len(), 12 + len.min(255));
            let decoded = codec::decode(&bytes, None);
            assert!(decoded.messages.is_empty());
            assert_eq!(
                decoded.rejected,
                vec![codec::Rejection::Undecodable {
                    message_id: id & 0x00ff_ffff
                }]
            );
        }
    }

    #[test]
    fn signed_frames_verify_and_wrong_keys_do_not() {
        let key = [0x5a; 32];
        let signature = Signature::now(key);
        let original = samples()[1].clone();
        let bytes = signed_message(200, 190, 1, &original, &signature);
        let ours = SigningData::from_config(SigningConfig::new(key, 0, false, false));
        assert_eq!(read(&bytes, Some(&ours)).map(|(_, m)| m), Some(original));

        let sitl = codec::Signing::new(key);
        let fresh = signed_message(
            200,
            190,
            2,
            &samples()[0],
            &Signature {
                timestamp: signature.timestamp + 1,
                ..signature
            },
        );
        assert_eq!(codec::decode(&fresh, Some(&sitl)).messages.len(), 1);

        let wrong = signed_message(200, 190, 3, &samples()[0], &Signature::now([0x5b; 32]));
        assert_eq!(
            codec::decode(&wrong, Some(&codec::Signing::new(key))).rejected,
            vec![codec::Rejection::BadSignature]
        );
        let mut flagged = Frame::of_message(200, 190, 4, &samples()[0]);
        flagged.incompat_flags = IFLAG_SIGNED;
        assert_eq!(
            codec::decode(&flagged.to_bytes(), Some(&codec::Signing::new(key))).rejected,
            vec![codec::Rejection::BadSignature]
        );
    }

    #[test]
    fn unknown_incompatibility_flags_are_dropped_by_the_codec() {
        let heartbeat = MavMessage::HEARTBEAT(HEARTBEAT_DATA {
            custom_mode: 7,
            mavtype: MavType::MAV_TYPE_GCS,
            autopilot: MavAutopilot::MAV_AUTOPILOT_INVALID,
            base_mode: MavModeFlag::empty(),
            system_status: MavState::MAV_STATE_ACTIVE,
            mavlink_version: 3,
        });
        let header = MavHeader {
            system_id: 255,
            component_id: 190,
            sequence: 4,
        };
        for flag in [0x02u8, 0x04, 0x80] {
            let mut frame = Frame::of_message(255, 190, 0, &heartbeat);
            frame.incompat_flags = flag;
            let mut bytes = frame.to_bytes();
            // forge clears 0x02; set it by hand and fix the CRC.
            bytes[2] = flag;
            let crc_at = bytes.len() - 2;
            let crc = mavlink::calculate_crc(&bytes[1..crc_at], crc_extra(0));
            bytes[crc_at..].copy_from_slice(&crc.to_le_bytes());
            let decoded = codec::decode(&bytes, None);
            assert!(
                decoded.messages.is_empty() && decoded.rejected.is_empty(),
                "flag {flag:#x}"
            );
        }
        let mut good = codec::encode(header, &heartbeat, None);
        good.extend(codec::encode(header, &heartbeat, None));
        assert_eq!(codec::decode(&good, None).messages.len(), 2);
    }
}
