//! The OPC UA side of `ladderc serve` (async-opcua): the devices as
//! variables under Objects/PLC, one folder per kind (X, Y, M, S, T, TN, C,
//! CN, D, R, ...), with node ids named as the watch list names them
//! (`ns=2;s=D100`, `ns=2;s=D100:32`, `ns=2;s=D20:float`). Bits are Boolean,
//! words Int16, pairs and 32-bit counters Int32, real numbers Float. Reads
//! and subscriptions sample the image the latest scan published (at
//! intervals down to the scan period); writes are queued as host writes,
//! as Modbus and HTTP writes are, and answered Good once applied (a read
//! after the answer sees them). The address space and its writes are
//! `opcua_nodes`'; this file is the server: endpoint, users, limits.
//!
//! Access follows the HTTP rules: with `--token-file` an anonymous session
//! reads only and the user `operator` with the token as password writes;
//! without one, anonymous sessions write only when the server listens on
//! loopback (OPC UA does not tell a variable who the peer is, so a server
//! beyond loopback without a token is read-only); `--read-only` makes every
//! variable read-only.

use super::opcua_nodes;
use super::shared::Shared;
use ladder_engine::waveform::Signal;
use ladder_runtime::Device;
use opcua::server::address_space::AccessLevel;
use opcua::server::authenticator::{AuthManager, DefaultAuthenticator, Password, UserToken};
use opcua::server::diagnostics::NamespaceMetadata;
use opcua::server::{ServerBuilder, ServerEndpoint, ServerUserToken, ANONYMOUS_USER_TOKEN_ID};
use opcua::types::{NodeId, UserTokenPolicy};
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
        .with_node_manager(opcua_nodes::manager(
            opcua_nodes::Setup {
                namespace: NamespaceMetadata {
                    namespace_uri: NAMESPACE.to_string(),
                    ..Default::default()
                },
                devices: setup.devices,
                read_only: setup.read_only,
                period_ms,
            },
            shared,
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
    let listener = setup.listener;
    Ok(async move {
        // The directory lives as long as the server.
        let _pki = pki;
        let _handle = handle;
        let _ = server.run_with(listener).await;
    })
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
    use super::opcua_nodes::{folder_of, kind_of, Kind};
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
}
