//! The OPC UA side of `ladderc serve` (async-opcua): the devices as
//! variables under Objects/PLC, one folder per kind (X, Y, M, S, T, TN, C,
//! CN, D, R, ...), with node ids named as the watch list names them
//! (`ns=2;s=D100`, `ns=2;s=D100:32`, `ns=2;s=D20:float`). Bits are Boolean,
//! words Int16, pairs and 32-bit counters Int32, real numbers Float. Reads
//! and subscriptions sample the image the latest scan published (at
//! intervals down to the scan period); writes are queued as host writes,
//! as Modbus and HTTP writes are, and answered Good once applied (a read
//! after the answer sees them).
//!
//! Access follows the HTTP rules: with `--token-file` an anonymous session
//! reads only and the user `operator` with the token as password writes;
//! without one, anonymous sessions write only when the server listens on
//! loopback (OPC UA does not tell a variable who the peer is, so a server
//! beyond loopback without a token is read-only); `--read-only` makes every
//! variable read-only.

use super::acks::{NotApplied, Ticket};
use super::shared::{HostWrite, Shared};
use ladder_engine::waveform::Signal;
use ladder_runtime::{Device, Width};
use opcua::server::address_space::{AccessLevel, VariableBuilder};
use opcua::server::authenticator::{AuthManager, DefaultAuthenticator, Password, UserToken};
use opcua::server::diagnostics::NamespaceMetadata;
use opcua::server::node_manager::memory::{simple_node_manager, SimpleNodeManager};
use opcua::server::{ServerBuilder, ServerEndpoint, ServerUserToken, ANONYMOUS_USER_TOKEN_ID};
use opcua::types::{
    DataTypeId, DataValue, DateTime, NodeId, ObjectId, QualifiedName, StatusCode, UserTokenPolicy, Variant,
};
use std::collections::BTreeMap;
use std::sync::Arc;
use std::time::Duration;

/// The namespace of the devices.
pub const NAMESPACE: &str = "urn:ladderc:plc";
/// The user who writes when a token is required.
pub const WRITER: &str = "operator";
/// The devices published unless `--opcua-devices` names others.
pub const DEFAULT_DEVICES: &str =
    "X0..X377,Y0..Y377,M0..M1023,M8000..M8099,S0..S999,T0..T255,TN0..TN255,C0..C255,CN0..CN199,CN200..CN255,D0..D1023,D8000..D8099,R0..R1023";

/// How a device shows in OPC UA.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Kind {
    Boolean,
    Int16,
    Int32,
    Float,
}

fn kind_of(signal: &Signal) -> Kind {
    if signal.real {
        return Kind::Float;
    }
    match (signal.device.device, signal.device.width) {
        (Device::Bit(..) | Device::WordBit(..), Width::Single | Width::Double) => Kind::Boolean,
        (Device::WideCounter(_), Width::Single | Width::Double)
        | (Device::Word(..) | Device::Digits(..), Width::Double) => Kind::Int32,
        (Device::Word(..) | Device::Digits(..), Width::Single) => Kind::Int16,
    }
}

fn variant(kind: Kind, raw: i32) -> Variant {
    match kind {
        Kind::Boolean => Variant::Boolean(raw != 0),
        Kind::Int16 => Variant::Int16(raw as i16),
        Kind::Int32 => Variant::Int32(raw),
        Kind::Float => Variant::Float(f32::from_bits(raw as u32)),
    }
}

/// The raw value a client's variant writes, if it has the variable's type
/// (integers of another width are taken when they fit).
fn raw_of(kind: Kind, value: &Variant) -> Option<i32> {
    // async-opcua's values: any other type (strings, arrays, ...) is no integer.
    #[allow(clippy::wildcard_enum_match_arm)]
    let integer = match value {
        Variant::Boolean(b) => Some(i64::from(*b)),
        Variant::SByte(v) => Some(i64::from(*v)),
        Variant::Byte(v) => Some(i64::from(*v)),
        Variant::Int16(v) => Some(i64::from(*v)),
        Variant::UInt16(v) => Some(i64::from(*v)),
        Variant::Int32(v) => Some(i64::from(*v)),
        Variant::UInt32(v) => Some(i64::from(*v)),
        Variant::Int64(v) => Some(*v),
        Variant::UInt64(v) => i64::try_from(*v).ok(),
        _ => None,
    };
    match kind {
        Kind::Boolean => match (value, integer) {
            (Variant::Boolean(b), _) => Some(i32::from(*b)),
            (_, Some(n @ 0..=1)) => Some(n as i32),
            _ => None,
        },
        Kind::Int16 => integer.and_then(|n| i16::try_from(n).ok().map(i32::from)),
        Kind::Int32 => integer.and_then(|n| i32::try_from(n).ok()),
        Kind::Float => real_of(value),
    }
}

/// A real number's bits: a Float, or a Double rounded to one.
// async-opcua's values: any other type is no real number.
#[allow(clippy::wildcard_enum_match_arm)]
fn real_of(value: &Variant) -> Option<i32> {
    match value {
        Variant::Float(f) => Some(f.to_bits() as i32),
        Variant::Double(d) => Some((*d as f32).to_bits() as i32),
        _ => None,
    }
}

/// The folder of a device: the letters its name starts with.
fn folder_of(name: &str) -> String {
    name.chars().take_while(char::is_ascii_alphabetic).collect()
}

/// Who may write: the default authenticator for identities, and the
/// anonymous sessions' write permission.
struct Gate {
    users: DefaultAuthenticator,
    anonymous_writes: bool,
}

#[async_trait::async_trait]
impl AuthManager for Gate {
    async fn authenticate_anonymous_token(&self, endpoint: &ServerEndpoint) -> Result<(), opcua::types::Error> {
        self.users.authenticate_anonymous_token(endpoint).await
    }

    async fn authenticate_username_identity_token(
        &self,
        endpoint: &ServerEndpoint,
        username: &str,
        password: &Password,
    ) -> Result<UserToken, opcua::types::Error> {
        self.users
            .authenticate_username_identity_token(endpoint, username, password)
            .await
    }

    fn effective_user_access_level(&self, token: &UserToken, level: AccessLevel, _node: &NodeId) -> AccessLevel {
        if token.is_anonymous() && !self.anonymous_writes {
            level - AccessLevel::CURRENT_WRITE
        } else {
            level
        }
    }

    fn user_token_policies(&self, endpoint: &ServerEndpoint) -> Vec<UserTokenPolicy> {
        self.users.user_token_policies(endpoint)
    }
}

/// What the OPC UA server needs to know.
pub struct Setup {
    pub listener: tokio::net::TcpListener,
    pub devices: Vec<Signal>,
    pub read_only: bool,
    pub token: Option<String>,
    pub period: Duration,
}

/// Builds the server and its address space; the returned future serves
/// until the process ends. `Err` is a message for an unusable setup.
pub fn start(
    setup: Setup,
    shared: Arc<Shared>,
) -> Result<impl std::future::Future<Output = ()> + Send + 'static, String> {
    let bound = setup.listener.local_addr().map_err(|e| e.to_string())?;
    let anonymous_writes = !setup.read_only && setup.token.is_none() && bound.ip().is_loopback();
    let mut user_tokens = vec![ANONYMOUS_USER_TOKEN_ID.to_string()];
    let mut users = BTreeMap::new();
    if let Some(token) = &setup.token {
        users.insert(
            WRITER.to_string(),
            ServerUserToken {
                user: WRITER.to_string(),
                pass: Some(token.clone()),
                ..Default::default()
            },
        );
        user_tokens.push(WRITER.to_string());
    }
    // Certificates are not used (security policy None); the library still
    // wants a directory for them, which must not be the user's.
    let pki = tempfile::tempdir().map_err(|e| format!("OPC UA: {e}"))?;
    let period_ms = setup.period.as_millis().max(1) as f64;
    let endpoint_url = format!("opc.tcp://{bound}/");
    let mut builder = ServerBuilder::new()
        .application_name("ladderc soft PLC")
        .application_uri("urn:ladderc:soft-plc")
        .product_uri("urn:ladderc")
        .host(bound.ip().to_string())
        .port(bound.port())
        .pki_dir(pki.path())
        .create_sample_keypair(false)
        .add_endpoint("none", ServerEndpoint::new_none("/", &user_tokens))
        .discovery_urls(vec![endpoint_url])
        .subscription_poll_interval_ms(setup.period.as_millis().clamp(1, 100) as u64)
        .diagnostics_enabled(false)
        .with_authenticator(Arc::new(Gate {
            users: DefaultAuthenticator::new(users.clone()),
            anonymous_writes,
        }))
        .with_node_manager(simple_node_manager(
            NamespaceMetadata {
                namespace_uri: NAMESPACE.to_string(),
                ..Default::default()
            },
            "ladderc",
        ));
    for (id, user) in users {
        builder = builder.add_user_token(id, user);
    }
    {
        let limits = &mut builder.limits_mut().subscriptions;
        limits.min_sampling_interval_ms = period_ms;
        limits.min_publishing_interval_ms = period_ms.max(10.0);
    }
    let (server, handle) = builder.build().map_err(|e| format!("OPC UA: {e}"))?;
    let manager = handle
        .node_managers()
        .get_of_type::<SimpleNodeManager>()
        .ok_or("OPC UA: the device namespace is missing")?;
    let ns = handle
        .get_namespace_index(NAMESPACE)
        .ok_or("OPC UA: the device namespace has no index")?;
    let root = NodeId::new(ns, "PLC");
    {
        let mut space = manager.address_space().write();
        space.add_folder(
            &root,
            QualifiedName::new(ns, "PLC"),
            "PLC",
            &ObjectId::ObjectsFolder.into(),
        );
        let mut folders = std::collections::BTreeSet::new();
        for signal in &setup.devices {
            let folder_name = folder_of(&signal.name);
            let folder = NodeId::new(ns, format!("PLC/{folder_name}"));
            if folders.insert(folder_name.clone()) {
                space.add_folder(
                    &folder,
                    QualifiedName::new(ns, folder_name.as_str()),
                    folder_name.as_str(),
                    &root,
                );
            }
            let kind = kind_of(signal);
            let data_type = match kind {
                Kind::Boolean => DataTypeId::Boolean,
                Kind::Int16 => DataTypeId::Int16,
                Kind::Int32 => DataTypeId::Int32,
                Kind::Float => DataTypeId::Float,
            };
            let id = NodeId::new(ns, signal.name.clone());
            let mut variable =
                VariableBuilder::new(&id, QualifiedName::new(ns, signal.name.as_str()), signal.name.as_str())
                    .data_type(data_type)
                    .value(variant(kind, 0))
                    .minimum_sampling_interval(period_ms)
                    .organized_by(folder);
            if !setup.read_only {
                variable = variable.writable();
            }
            variable.insert(&mut *space);
        }
    }
    let inner = manager.inner();
    for signal in setup.devices {
        let kind = kind_of(&signal);
        let id = NodeId::new(ns, signal.name.clone());
        let device = signal.device;
        let reader = Arc::clone(&shared);
        inner.add_read_callback(id.clone(), move |_, _, _| {
            let raw = reader.image().read_device(device.device, device.width).unwrap_or(0);
            let now = DateTime::now();
            Ok(DataValue::new_at(variant(kind, raw), now))
        });
        if !setup.read_only {
            let writer = Arc::clone(&shared);
            inner.add_write_callback(id, move |value, range| {
                if range.has_range() {
                    return StatusCode::BadIndexRangeInvalid;
                }
                let Some(raw) = value.value.as_ref().and_then(|v| raw_of(kind, v)) else {
                    return StatusCode::BadTypeMismatch;
                };
                let Some(ticket) = writer.queue(vec![HostWrite::Set(device, raw)]) else {
                    // The queue of writes is full.
                    return StatusCode::BadTooManyOperations;
                };
                match wait_applied(&writer, ticket) {
                    Ok(()) => StatusCode::Good,
                    Err(NotApplied::TimedOut) => StatusCode::BadTimeout,
                    Err(NotApplied::Stopping) => StatusCode::BadShutdown,
                }
            });
        }
    }
    let listener = setup.listener;
    Ok(async move {
        // The directory lives as long as the server.
        let _pki = pki;
        let _handle = handle;
        let _ = server.run_with(listener).await;
    })
}

/// Waits for a write to be applied in async-opcua's write callback, which
/// is not async: the runtime is told this worker blocks (bounded by
/// `acks::WRITE_WAIT`), so its other tasks move on.
fn wait_applied(shared: &Shared, ticket: Ticket) -> Result<(), NotApplied> {
    let multi_thread = tokio::runtime::Handle::try_current()
        .is_ok_and(|handle| handle.runtime_flavor() == tokio::runtime::RuntimeFlavor::MultiThread);
    if multi_thread {
        tokio::task::block_in_place(|| shared.wait_applied(ticket))
    } else {
        shared.wait_applied(ticket)
    }
}

/// The devices of `--opcua-devices` (the watch list's syntax).
pub fn parse_devices(text: &str) -> Result<Vec<Signal>, String> {
    let mut devices = Vec::new();
    let mut seen = std::collections::HashSet::new();
    for entry in text.split(',').map(str::trim).filter(|e| !e.is_empty()) {
        for mut signal in ladder_engine::watch::parse_watch(entry)? {
            // Contacts of timers and counters are named as FX names them
            // (T0, C0: the node `ns=2;s=T0`), not as a watch list shows them.
            match signal.device.device {
                Device::Bit(ladder_runtime::BitArea::TimerContact, n) => signal.name = format!("T{n}"),
                Device::Bit(ladder_runtime::BitArea::CounterContact, n) => signal.name = format!("C{n}"),
                Device::Bit(..)
                | Device::Word(..)
                | Device::WordBit(..)
                | Device::Digits(..)
                | Device::WideCounter(_) => {}
            }
            if seen.insert(signal.name.clone()) {
                devices.push(signal);
            }
        }
    }
    if devices.is_empty() {
        return Err("--opcua-devices names no device".to_string());
    }
    Ok(devices)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn devices_get_their_types_and_folders() {
        let contacts = parse_devices("T0,C3,TN0").unwrap();
        let names: Vec<&str> = contacts.iter().map(|s| s.name.as_str()).collect();
        assert_eq!(names, ["T0", "C3", "TN0"], "contacts as FX names them");
        let devices = parse_devices("X0..X1,D10,D20:32,D30:float,CN200,TN5").unwrap();
        let kinds: Vec<(String, Kind, String)> = devices
            .iter()
            .map(|s| (s.name.clone(), kind_of(s), folder_of(&s.name)))
            .collect();
        assert_eq!(kinds[0].1, Kind::Boolean);
        assert_eq!(kinds[2], ("D10".to_string(), Kind::Int16, "D".to_string()));
        assert_eq!(kinds[3].1, Kind::Int32);
        assert_eq!(kinds[4].1, Kind::Float);
        assert_eq!(kinds[5].1, Kind::Int32);
        assert_eq!(kinds[6].2, "TN");
        assert!(parse_devices(DEFAULT_DEVICES).is_ok());
    }

    #[test]
    fn writes_take_values_that_fit() {
        assert_eq!(raw_of(Kind::Int16, &Variant::Int32(-5)), Some(-5));
        assert_eq!(raw_of(Kind::Int16, &Variant::Int32(40_000)), None);
        assert_eq!(raw_of(Kind::Boolean, &Variant::Boolean(true)), Some(1));
        assert_eq!(raw_of(Kind::Boolean, &Variant::Int16(2)), None);
        assert_eq!(raw_of(Kind::Float, &Variant::Float(1.5)), Some(1.5f32.to_bits() as i32));
        assert_eq!(raw_of(Kind::Float, &Variant::Int16(1)), None);
        assert_eq!(raw_of(Kind::Int32, &Variant::UInt32(u32::MAX)), None);
    }
}
