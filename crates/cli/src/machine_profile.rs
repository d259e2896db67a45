//! Finding a machine profile: the application layer does it for the CLI and the server.

pub(crate) use oficina_app::profile::{parse_xyz, resolve, resolve_with_offset, DEFAULT};
