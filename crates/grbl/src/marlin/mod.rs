//! The Marlin link (Marlin 2.x, and Makelangelo's firmware built on it): numbered,
//! checksummed lines one at a time ([`MarlinLink`]), over the grbl link's transports
//! ([`crate::Endpoint`]), journalled like a grbl stream, and a [`MarlinDevice`] behind
//! Oficina's `Machine` trait for `oficina run --machine marlin:/dev/ttyUSB0`.

mod device;
mod frame;
mod program;
mod resume;
mod sender;

pub use device::{marlin_endpoint, MarlinDevice};
pub use frame::{checksum, code_of, frame, strip_comment, Reply, MAX_CMD_SIZE};
pub use program::marlin_program;
pub use resume::{plan_resume, MarlinResume};
pub use sender::{MarlinControl, MarlinEnd, MarlinLink, MarlinNotice, MarlinOptions, MarlinReport};
