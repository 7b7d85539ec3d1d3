//! An EtherCAT port on a Linux network interface: raw Ethernet frames in and out through an
//! `AF_PACKET` socket (via `pnet_datalink`).

use std::fmt;
use std::io;
use std::time::Duration;

use pnet_datalink::{Channel, Config, DataLinkReceiver, DataLinkSender, NetworkInterface};

/// How long a receive waits before the receiving thread looks at its stop flag again.
pub const RECEIVE_POLL: Duration = Duration::from_millis(100);
/// The socket's receive buffer, in bytes: what arrives while the line is busy waits there. A
/// small frame takes about 800 bytes of it (the kernel's accounting), so 16 MiB hold a burst of
/// some 20 000 frames; the default (208 KiB) held about 270. Needs `CAP_NET_ADMIN` beyond
/// `net.core.rmem_max`; without it the buffer is as large as that allows.
pub const RECEIVE_BUFFER: usize = 16 << 20;

/// Why an interface could not be opened.
#[derive(Debug)]
pub enum OpenError {
    /// No interface of that name; the names that exist.
    NoSuchInterface {
        /// The name asked for.
        name: String,
        /// The interfaces the system has.
        available: Vec<String>,
    },
    /// Raw sockets need root or `CAP_NET_RAW`.
    NotPermitted(io::Error),
    /// Any other failure of the socket.
    Io(io::Error),
}

impl fmt::Display for OpenError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::NoSuchInterface { name, available } => write!(
                f,
                "no network interface named {name:?} (available: {})",
                available.join(", ")
            ),
            Self::NotPermitted(e) => write!(
                f,
                "cannot open a raw socket ({e}): run as root or grant the binary CAP_NET_RAW \
                 (sudo setcap cap_net_raw+ep <binary>)"
            ),
            Self::Io(e) => write!(f, "cannot open a raw socket: {e}"),
        }
    }
}

impl std::error::Error for OpenError {}

/// The sending and receiving halves of a raw socket on one interface.
pub struct Port {
    /// Sends frames.
    pub tx: Box<dyn DataLinkSender>,
    /// Receives frames; a receive times out after [`RECEIVE_POLL`].
    pub rx: Box<dyn DataLinkReceiver>,
}

/// Opens a raw socket on the interface `name`.
pub fn open(name: &str) -> Result<Port, OpenError> {
    let interfaces = pnet_datalink::interfaces();
    let Some(interface) = interfaces.iter().find(|i| i.name == name) else {
        return Err(OpenError::NoSuchInterface {
            name: name.to_owned(),
            available: interfaces
                .iter()
                .map(|i: &NetworkInterface| i.name.clone())
                .collect(),
        });
    };
    let socket = match raw_socket() {
        Ok(socket) => socket,
        Err(e) if e.kind() == io::ErrorKind::PermissionDenied => {
            return Err(OpenError::NotPermitted(e));
        }
        Err(e) => return Err(OpenError::Io(e)),
    };
    let config = Config {
        read_timeout: Some(RECEIVE_POLL),
        promiscuous: true,
        socket_fd: Some(socket),
        ..Config::default()
    };
    match pnet_datalink::channel(interface, config) {
        Ok(Channel::Ethernet(tx, rx)) => Ok(Port { tx, rx }),
        Ok(_) => Err(OpenError::Io(io::Error::other("not an Ethernet channel"))),
        Err(e) if e.kind() == io::ErrorKind::PermissionDenied => Err(OpenError::NotPermitted(e)),
        Err(e) => Err(OpenError::Io(e)),
    }
}

/// An `AF_PACKET` raw socket for every protocol, with a [`RECEIVE_BUFFER`] (forced past
/// `net.core.rmem_max` where allowed), for `pnet_datalink` to bind and own.
fn raw_socket() -> io::Result<i32> {
    use std::os::fd::IntoRawFd;

    use nix::sys::socket::{
        AddressFamily, SockFlag, SockProtocol, SockType, setsockopt, socket, sockopt,
    };
    let socket = socket(
        AddressFamily::Packet,
        SockType::Raw,
        SockFlag::SOCK_CLOEXEC,
        SockProtocol::EthAll,
    )?;
    if setsockopt(&socket, sockopt::RcvBufForce, &RECEIVE_BUFFER).is_err() {
        setsockopt(&socket, sockopt::RcvBuf, &RECEIVE_BUFFER)?;
    }
    Ok(socket.into_raw_fd())
}

/// Whether `frame` is an EtherCAT frame (EtherType 0x88A4).
pub fn is_ethercat(frame: &[u8]) -> bool {
    let ethertype = frame
        .get(12..14)
        .and_then(|t| t.try_into().ok())
        .map(u16::from_be_bytes);
    ethertype == Some(ecat_emu::frame::ETHERTYPE)
}

/// Whether the source MAC of `frame` has the locally-administered bit set (bit 1 of its first
/// byte), as an ESC sets it on every frame it processes.
pub fn locally_administered(frame: &[u8]) -> bool {
    frame.get(6).is_some_and(|byte| byte & 0x02 != 0)
}

/// The frames this program sent last: an `AF_PACKET` socket also receives its own outgoing
/// frames, which must not be processed again. Recognised by content (a hash) where the source
/// MAC does not tell: a foreign frame goes back unchanged, and with `--la-requests` (a
/// MainDevice whose interface MAC has the locally-administered bit set, veth, QEMU) the bit is
/// no mark of an answer.
#[derive(Debug, Default)]
pub struct Sent(std::collections::VecDeque<u64>);

impl Sent {
    /// How many sent frames are remembered.
    const CAPACITY: usize = 256;

    /// Remembers `frame` as sent.
    pub fn push(&mut self, frame: &[u8]) {
        if self.0.len() == Self::CAPACITY {
            self.0.pop_front();
        }
        self.0.push_back(hash(frame));
    }

    /// Whether `frame` is one this program sent (forgotten once recognised).
    pub fn take(&mut self, frame: &[u8]) -> bool {
        let h = hash(frame);
        match self.0.iter().position(|&s| s == h) {
            Some(i) => {
                self.0.remove(i);
                true
            }
            None => false,
        }
    }
}

fn hash(frame: &[u8]) -> u64 {
    use std::hash::{Hash, Hasher};
    let mut hasher = std::collections::hash_map::DefaultHasher::new();
    frame.hash(&mut hasher);
    hasher.finish()
}

/// Whether a receive error only means that no frame arrived in time.
pub fn is_timeout(e: &io::Error) -> bool {
    matches!(
        e.kind(),
        io::ErrorKind::TimedOut | io::ErrorKind::WouldBlock | io::ErrorKind::Interrupted
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn frame(source0: u8, ethertype: [u8; 2]) -> Vec<u8> {
        let mut f = vec![0xFF; 6];
        f.extend_from_slice(&[source0, 0x10, 0x10, 0x10, 0x10, 0x10]);
        f.extend_from_slice(&ethertype);
        f.extend_from_slice(&[0; 46]);
        f
    }

    #[test]
    fn ethercat_frames_are_told_by_their_ethertype() {
        assert!(is_ethercat(&frame(0x10, [0x88, 0xA4])));
        assert!(
            is_ethercat(&frame(0x12, [0x88, 0xA4])),
            "a locally administered MAC too"
        );
        assert!(!is_ethercat(&frame(0x10, [0x08, 0x00])), "IPv4");
        assert!(!is_ethercat(&[0x10; 13]), "truncated");
    }

    #[test]
    fn own_frames_are_recognised_once_whatever_their_source_mac() {
        let mut sent = Sent::default();
        let reply = frame(0x12, [0x88, 0xA4]);
        let request = frame(0x02, [0x88, 0xA4]);
        sent.push(&reply);
        assert!(
            !sent.take(&request),
            "a MainDevice's frame with the LA bit set"
        );
        assert!(sent.take(&reply), "our own reply, seen by the raw socket");
        assert!(!sent.take(&reply), "forgotten once recognised");
        for n in 0..=Sent::CAPACITY {
            sent.push(&[n as u8, (n >> 8) as u8]);
        }
        assert!(!sent.take(&[0, 0]), "the oldest is forgotten");
        assert!(sent.take(&[1, 0]));
    }

    #[test]
    fn a_missing_interface_lists_the_available_ones() {
        let Err(e) = open("no-such-if0") else {
            panic!("opened a missing interface")
        };
        let text = e.to_string();
        assert!(
            text.starts_with("no network interface named \"no-such-if0\""),
            "{text}"
        );
        assert!(text.contains("lo"), "{text}");
    }
}
