//! Byte transports to the firmware: a serial port (USB grbl boards), a raw TCP socket
//! (grblHAL / FluidNC "telnet" ports) and, for the emulator, a pseudo-terminal. Each opens
//! into a reader and a writer half so that one thread can wait for replies while another
//! writes real-time bytes.

use std::fmt;
use std::fs::File;
use std::io::{self, Read, Write};
use std::net::{TcpStream, ToSocketAddrs};
use std::str::FromStr;
use std::time::Duration;

/// How long a blocked read waits before the reader loop looks around (closing, etc.).
pub(crate) const READ_POLL: Duration = Duration::from_millis(50);

/// Where the firmware is.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Endpoint {
    /// A serial port.
    Serial {
        /// Device path.
        path: String,
        /// Baud rate.
        baud: u32,
    },
    /// A TCP socket (grblHAL or FluidNC over the network).
    Tcp {
        /// `host:port`.
        addr: String,
    },
}

impl FromStr for Endpoint {
    type Err = String;
    /// Accepts `grbl:/dev/ttyUSB0`, `/dev/ttyUSB0@115200`, `serial:COM3@250000`,
    /// `tcp://192.168.1.5:23`, `telnet://fluidnc.local` (port 23) and `grbl:tcp://…`.
    fn from_str(s: &str) -> Result<Self, String> {
        let s = s.trim();
        let s = s.strip_prefix("grbl:").unwrap_or(s);
        if let Some(addr) = s.strip_prefix("tcp://") {
            if addr.is_empty() || !addr.contains(':') {
                return Err(format!(
                    "tcp address '{addr}' needs HOST:PORT, e.g. tcp://192.168.1.5:23 (or telnet://HOST for port 23)"
                ));
            }
            return Ok(Endpoint::Tcp {
                addr: addr.to_string(),
            });
        }
        // grblHAL's and FluidNC's raw "telnet" port: 23 unless given.
        if let Some(host) = s.strip_prefix("telnet://") {
            if host.is_empty() {
                return Err(
                    "telnet address is empty: use telnet://HOST or telnet://HOST:PORT".into(),
                );
            }
            let addr = if host.contains(':') {
                host.to_string()
            } else {
                format!("{host}:23")
            };
            return Ok(Endpoint::Tcp { addr });
        }
        let s = s.strip_prefix("serial:").unwrap_or(s);
        if s.is_empty() {
            return Err("empty machine address: use grbl:/dev/ttyUSB0, grbl:/dev/ttyUSB0@115200 or tcp://HOST:PORT".into());
        }
        let (path, baud) = match s.rsplit_once('@') {
            Some((p, b)) => (
                p,
                b.parse()
                    .map_err(|_| format!("baud rate '{b}' in '{s}' is not a number"))?,
            ),
            None => (s, 115_200),
        };
        Ok(Endpoint::Serial {
            path: path.to_string(),
            baud,
        })
    }
}

impl fmt::Display for Endpoint {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Endpoint::Serial { path, baud } => write!(f, "{path}@{baud}"),
            Endpoint::Tcp { addr } => write!(f, "tcp://{addr}"),
        }
    }
}

/// The two halves of an open connection. Reads time out after [`READ_POLL`] with
/// `TimedOut`/`WouldBlock`, which callers treat as "nothing yet".
pub struct Connection {
    pub reader: Box<dyn Read + Send>,
    pub writer: Box<dyn Write + Send>,
}

/// Opens the endpoint. The error names the endpoint and the cause.
pub(crate) fn open(endpoint: &Endpoint) -> io::Result<Connection> {
    let named = |e: io::Error| io::Error::new(e.kind(), format!("cannot open {endpoint}: {e}"));
    match endpoint {
        Endpoint::Serial { path, baud } => {
            let port = serialport::new(path, *baud)
                .timeout(READ_POLL)
                .data_bits(serialport::DataBits::Eight)
                .parity(serialport::Parity::None)
                .stop_bits(serialport::StopBits::One)
                .flow_control(serialport::FlowControl::None)
                .open()
                .map_err(|e| named(e.into()))?;
            let writer = port.try_clone().map_err(|e| named(e.into()))?;
            Ok(Connection {
                reader: Box::new(port),
                writer: Box::new(writer),
            })
        }
        Endpoint::Tcp { addr } => {
            let target = addr
                .to_socket_addrs()
                .map_err(named)?
                .next()
                .ok_or_else(|| {
                    named(io::Error::new(
                        io::ErrorKind::NotFound,
                        "address resolves to nothing",
                    ))
                })?;
            let stream =
                TcpStream::connect_timeout(&target, Duration::from_secs(5)).map_err(named)?;
            stream.set_nodelay(true).map_err(named)?;
            stream.set_read_timeout(Some(READ_POLL)).map_err(named)?;
            let writer = stream.try_clone().map_err(named)?;
            Ok(Connection {
                reader: Box::new(stream),
                writer: Box::new(writer),
            })
        }
    }
}

/// A serial port the system knows of.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct PortInfo {
    /// Device path (`/dev/ttyUSB0`).
    pub path: String,
    /// What it is (USB vendor/product, or the driver).
    pub kind: String,
}

/// Serial ports present now (USB adapters show their vendor/product).
pub fn list_ports() -> io::Result<Vec<PortInfo>> {
    let ports = serialport::available_ports().map_err(io::Error::from)?;
    Ok(ports
        .into_iter()
        .map(|p| {
            let kind = match p.port_type {
                serialport::SerialPortType::UsbPort(u) => format!(
                    "USB {:04x}:{:04x} {} {}",
                    u.vid,
                    u.pid,
                    u.manufacturer.unwrap_or_default(),
                    u.product.unwrap_or_default()
                )
                .trim()
                .to_string(),
                serialport::SerialPortType::PciPort => "PCI".into(),
                serialport::SerialPortType::BluetoothPort => "Bluetooth".into(),
                serialport::SerialPortType::Unknown => "unknown".into(),
            };
            PortInfo {
                path: p.port_name,
                kind,
            }
        })
        .collect())
}

/// Whether a read error only means "no byte yet".
pub fn is_timeout(e: &io::Error) -> bool {
    matches!(
        e.kind(),
        io::ErrorKind::TimedOut | io::ErrorKind::WouldBlock | io::ErrorKind::Interrupted
    )
}

/// The master side of a pseudo-terminal. The emulator keeps the slave open too, so a
/// sender may close and reopen the slave path (a "replugged cable") without the master
/// seeing a hang-up.
pub struct Pty {
    /// The master's file.
    pub master: File,
    /// The slave's path, to open as a serial port.
    pub slave_path: String,
    _slave: File,
}

impl Pty {
    /// Opens a pseudo-terminal in raw mode.
    pub fn open() -> io::Result<Pty> {
        use nix::sys::termios;
        let pair = nix::pty::openpty(None, None).map_err(io::Error::from)?;
        // Raw mode: no echo, no CR/LF translation, bytes pass as sent, like a UART.
        let mut t = termios::tcgetattr(&pair.slave).map_err(io::Error::from)?;
        termios::cfmakeraw(&mut t);
        termios::tcsetattr(&pair.slave, termios::SetArg::TCSANOW, &t).map_err(io::Error::from)?;
        let slave_path = nix::unistd::ttyname(&pair.slave)
            .map_err(io::Error::from)?
            .to_string_lossy()
            .into_owned();
        Ok(Pty {
            master: File::from(pair.master),
            slave_path,
            _slave: File::from(pair.slave),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn endpoints_parse() {
        assert_eq!(
            "grbl:/dev/ttyUSB0".parse::<Endpoint>().unwrap(),
            Endpoint::Serial {
                path: "/dev/ttyUSB0".into(),
                baud: 115_200
            }
        );
        assert_eq!(
            "COM3@250000".parse::<Endpoint>().unwrap(),
            Endpoint::Serial {
                path: "COM3".into(),
                baud: 250_000
            }
        );
        assert_eq!(
            "tcp://127.0.0.1:23".parse::<Endpoint>().unwrap(),
            Endpoint::Tcp {
                addr: "127.0.0.1:23".into()
            }
        );
        assert!("tcp://nohost".parse::<Endpoint>().is_err());
        assert_eq!(
            "telnet://fluidnc.local".parse::<Endpoint>().unwrap(),
            Endpoint::Tcp {
                addr: "fluidnc.local:23".into()
            }
        );
        assert_eq!(
            "grbl:telnet://10.0.0.5:2323".parse::<Endpoint>().unwrap(),
            Endpoint::Tcp {
                addr: "10.0.0.5:2323".into()
            }
        );
        assert!("telnet://".parse::<Endpoint>().is_err());
        assert!("/dev/x@fast"
            .parse::<Endpoint>()
            .unwrap_err()
            .contains("fast"));
        assert!("".parse::<Endpoint>().is_err());
    }

    #[test]
    fn pty_carries_bytes_both_ways() {
        let mut pty = Pty::open().unwrap();
        let mut conn = open(&Endpoint::Serial {
            path: pty.slave_path.clone(),
            baud: 115_200,
        })
        .unwrap();
        conn.writer.write_all(b"G0X1\n").unwrap();
        let mut buf = [0u8; 5];
        pty.master.read_exact(&mut buf).unwrap();
        assert_eq!(&buf, b"G0X1\n");
        pty.master.write_all(b"ok\r\n").unwrap();
        let mut got = Vec::new();
        let mut b = [0u8; 16];
        for _ in 0..40 {
            match conn.reader.read(&mut b) {
                Ok(n) => got.extend_from_slice(&b[..n]),
                Err(e) if is_timeout(&e) => {}
                Err(e) => panic!("{e}"),
            }
            if got.len() >= 4 {
                break;
            }
        }
        assert_eq!(got, b"ok\r\n");
    }
}
