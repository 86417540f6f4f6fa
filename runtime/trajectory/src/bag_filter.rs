//! Copying a bag's messages selectively: a lamp file without `/lamp/world` and its `lamp` record
//! is a plain ROS 2 bag of standard messages, which is how the `ros2` demonstration source's
//! tests make the bags a robot without lamp records.

use std::collections::BTreeMap;
use std::io::Cursor;

use mcap::records::MessageHeader;

use crate::error::TrajectoryError;
use crate::schema::PROFILE;

/// Copies the messages of the MCAP file `bytes` (named `name` in errors) for which `keep`,
/// given the message's topic and log time, returns a log time; each copied message is logged
/// and published at that time, with its channel and schema as they were. Metadata, attachments
/// and messages `keep` refuses are left out.
pub fn filter_bag(
    bytes: &[u8],
    name: &str,
    mut keep: impl FnMut(&str, u64) -> Option<u64>,
) -> Result<Vec<u8>, TrajectoryError> {
    let corrupt = |error: mcap::McapError| TrajectoryError::Corrupt {
        file: name.to_string(),
        record: 0,
        steps: 0,
        reason: error.to_string(),
    };
    let write_error = |error: mcap::McapError| TrajectoryError::Io {
        file: name.to_string(),
        action: "write",
        source: std::io::Error::other(error),
    };
    let mut writer = mcap::WriteOptions::new()
        .profile(PROFILE)
        .library(crate::writer::LIBRARY)
        .compression_threads(0)
        .create(Cursor::new(Vec::new()))
        .map_err(write_error)?;
    let mut channels = BTreeMap::new();
    for message in mcap::MessageStream::new(bytes).map_err(corrupt)? {
        let message = message.map_err(corrupt)?;
        let channel = &message.channel;
        let Some(log_time) = keep(&channel.topic, message.log_time) else { continue };
        let id = match channels.get(&channel.id) {
            Some(id) => *id,
            None => {
                let schema = match &channel.schema {
                    Some(schema) => writer
                        .add_schema(&schema.name, &schema.encoding, &schema.data)
                        .map_err(write_error)?,
                    None => 0,
                };
                let id = writer
                    .add_channel(
                        schema,
                        &channel.topic,
                        &channel.message_encoding,
                        &channel.metadata,
                    )
                    .map_err(write_error)?;
                channels.insert(channel.id, id);
                id
            }
        };
        let header = MessageHeader {
            channel_id: id,
            sequence: message.sequence,
            log_time,
            publish_time: log_time,
        };
        writer.write_to_known_channel(&header, &message.data).map_err(write_error)?;
    }
    writer.finish().map_err(write_error)?;
    Ok(writer.into_inner().into_inner())
}
