//! The devices' node manager of the OPC UA server: the variables under
//! Objects/PLC and their types, reads and subscriptions (async-opcua's
//! simple node manager, sampling the published image through its read
//! callbacks), and writes (our own). A Write request's values are checked
//! under a read lock of the address space, queued as one batch of host
//! writes, and the request is answered once that batch is applied, the
//! wait a task's with no lock held: the simple node manager calls its
//! write callbacks under the address space's write lock, so a write
//! waiting there for the end of a scan held up every Read, Browse and
//! subscription sample, and blocked the runtime's workers (two, shared by
//! every server) on that lock.

use super::acks::NotApplied;
use super::shared::{HostWrite, Shared};
use ladder_engine::waveform::Signal;
use ladder_front::host_device::HostDevice;
use ladder_runtime::{Device, Width};
use opcua::server::address_space::{validate_node_write, AddressSpace, VariableBuilder};
use opcua::server::diagnostics::NamespaceMetadata;
use opcua::server::node_manager::memory::{
    InMemoryNodeManagerBuilder, InMemoryNodeManagerImpl, InMemoryNodeManagerImplBuilder, SimpleNodeManagerBuilder,
    SimpleNodeManagerImpl,
};
use opcua::server::node_manager::{
    MethodCall, MonitoredItemRef, MonitoredItemUpdateRef, NodeManagerBuilder, ParsedReadValueId, ParsedWriteValue,
    RequestContext, ServerContext, WriteNode,
};
use opcua::server::CreateMonitoredItem;
use opcua::sync::RwLock;
use opcua::types::{
    AttributeId, DataTypeId, DataValue, DateTime, MonitoringMode, NodeClass, NodeId, ObjectId, QualifiedName,
    StatusCode, TimestampsToReturn, Variant,
};
use std::collections::HashMap;
use std::sync::Arc;

/// How a device shows in OPC UA.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Kind {
    Boolean,
    Int16,
    Int32,
    Float,
}

pub(crate) fn kind_of(signal: &Signal) -> Kind {
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
pub(crate) fn folder_of(name: &str) -> String {
    name.chars().take_while(char::is_ascii_alphabetic).collect()
}

/// What the address space holds and who writes to it.
pub struct Setup {
    pub namespace: NamespaceMetadata,
    pub devices: Vec<Signal>,
    pub read_only: bool,
    /// The shortest sampling interval of a variable (the scan period).
    pub period_ms: f64,
}

/// The node manager of the devices, built with the server.
pub fn manager(setup: Setup, shared: Arc<Shared>) -> impl NodeManagerBuilder {
    InMemoryNodeManagerBuilder::new(move |context: ServerContext, space: &mut AddressSpace| {
        let simple = SimpleNodeManagerBuilder::new(setup.namespace, "ladderc").build(context, space);
        let ns = simple.namespaces().first().map_or(0, |n| n.namespace_index);
        let devices = add_devices(space, ns, &setup.devices, setup.read_only, setup.period_ms);
        for (id, &(device, kind)) in &devices {
            let reader = Arc::clone(&shared);
            simple.add_read_callback(id.clone(), move |_, _, _| {
                let raw = reader.image().read_device(device.device, device.width).unwrap_or(0);
                Ok(DataValue::new_at(variant(kind, raw), DateTime::now()))
            });
        }
        Devices {
            simple,
            shared,
            devices,
        }
    })
}

/// Objects/PLC, a folder per kind of device and a variable per device;
/// each variable's device and type.
fn add_devices(
    space: &mut AddressSpace,
    ns: u16,
    signals: &[Signal],
    read_only: bool,
    period_ms: f64,
) -> HashMap<NodeId, (HostDevice, Kind)> {
    let root = NodeId::new(ns, "PLC");
    space.add_folder(
        &root,
        QualifiedName::new(ns, "PLC"),
        "PLC",
        &ObjectId::ObjectsFolder.into(),
    );
    let mut folders = std::collections::BTreeSet::new();
    let mut devices = HashMap::new();
    for signal in signals {
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
        if !read_only {
            variable = variable.writable();
        }
        variable.insert(space);
        devices.insert(id, (signal.device, kind));
    }
    devices
}

/// The devices' node manager: async-opcua's simple one for all but writes.
pub struct Devices {
    simple: SimpleNodeManagerImpl,
    shared: Arc<Shared>,
    devices: HashMap<NodeId, (HostDevice, Kind)>,
}

impl Devices {
    /// The host write of one node's write, checked as the simple node
    /// manager checks it (the node, the session's access, the type), or
    /// the status it is refused with.
    fn host_write(
        &self,
        context: &RequestContext,
        space: &AddressSpace,
        type_tree: &opcua::nodes::DefaultTypeTree,
        write: &ParsedWriteValue,
    ) -> Result<(HostDevice, i32, Kind), StatusCode> {
        let node = space.find(&write.node_id).ok_or(StatusCode::BadNodeIdUnknown)?;
        validate_node_write(node, context, write, type_tree)?;
        if node.node_class() != NodeClass::Variable || write.attribute_id != AttributeId::Value {
            return Err(StatusCode::BadNotWritable);
        }
        let &(device, kind) = self.devices.get(&write.node_id).ok_or(StatusCode::BadNotWritable)?;
        if write.index_range.has_range() {
            return Err(StatusCode::BadIndexRangeInvalid);
        }
        let raw = write
            .value
            .value
            .as_ref()
            .and_then(|value| raw_of(kind, value))
            .ok_or(StatusCode::BadTypeMismatch)?;
        Ok((device, raw, kind))
    }
}

#[async_trait::async_trait]
impl InMemoryNodeManagerImpl for Devices {
    async fn init(&self, space: &mut AddressSpace, context: ServerContext) {
        self.simple.init(space, context).await;
    }

    fn name(&self) -> &str {
        self.simple.name()
    }

    fn namespaces(&self) -> Vec<NamespaceMetadata> {
        self.simple.namespaces()
    }

    async fn read_values(
        &self,
        context: &RequestContext,
        space: &RwLock<AddressSpace>,
        nodes: &[&ParsedReadValueId],
        max_age: f64,
        timestamps_to_return: TimestampsToReturn,
    ) -> Vec<DataValue> {
        self.simple
            .read_values(context, space, nodes, max_age, timestamps_to_return)
            .await
    }

    async fn create_value_monitored_items(
        &self,
        context: &RequestContext,
        space: &RwLock<AddressSpace>,
        items: &mut [&mut &mut CreateMonitoredItem],
    ) {
        self.simple.create_value_monitored_items(context, space, items).await;
    }

    async fn modify_monitored_items(&self, context: &RequestContext, items: &[&MonitoredItemUpdateRef]) {
        self.simple.modify_monitored_items(context, items).await;
    }

    async fn set_monitoring_mode(&self, context: &RequestContext, mode: MonitoringMode, items: &[&MonitoredItemRef]) {
        self.simple.set_monitoring_mode(context, mode, items).await;
    }

    async fn delete_monitored_items(&self, context: &RequestContext, items: &[&MonitoredItemRef]) {
        self.simple.delete_monitored_items(context, items).await;
    }

    async fn call(
        &self,
        context: &RequestContext,
        space: &RwLock<AddressSpace>,
        methods_to_call: &mut [&mut &mut MethodCall],
    ) -> Result<(), StatusCode> {
        self.simple.call(context, space, methods_to_call).await
    }

    /// Every node's write checked and queued in one batch, then answered
    /// once the batch is applied (Good: a read after the answer sees it),
    /// waiting with no lock held.
    async fn write(
        &self,
        context: &RequestContext,
        space: &RwLock<AddressSpace>,
        nodes_to_write: &mut [&mut WriteNode],
    ) -> Result<(), StatusCode> {
        let checked: Vec<Option<(HostDevice, i32, Kind)>> = {
            let space = space.read();
            let type_tree = context.type_tree.read();
            nodes_to_write
                .iter_mut()
                .map(
                    |node| match self.host_write(context, &space, &type_tree, node.value()) {
                        Ok(write) => Some(write),
                        Err(status) => {
                            node.set_status(status);
                            None
                        }
                    },
                )
                .collect()
        };
        let batch: Vec<HostWrite> = checked
            .iter()
            .flatten()
            .map(|&(device, raw, _)| HostWrite::Set(device, raw))
            .collect();
        if batch.is_empty() {
            return Ok(());
        }
        let queued = if crate::remote_io::refused(&self.shared, &batch).is_some() {
            // A device the remote I/O writes before every scan (`--io`).
            Err(StatusCode::BadNotWritable)
        } else {
            self.shared.queue(batch).ok_or(StatusCode::BadTooManyOperations)
        };
        let status = match queued {
            // Refused, or the queue of writes is full.
            Err(status) => status,
            Ok(ticket) => match self.shared.applied(ticket).await {
                Ok(()) => StatusCode::Good,
                Err(NotApplied::TimedOut) => StatusCode::BadTimeout,
                Err(NotApplied::Stopping) => StatusCode::BadShutdown,
            },
        };
        let image = self.shared.image();
        let now = DateTime::now();
        let mut changed = Vec::new();
        for (node, checked) in nodes_to_write.iter_mut().zip(&checked) {
            let Some((device, _, kind)) = checked else {
                continue;
            };
            node.set_status(status);
            if status.is_good() {
                // Subscribers see the value the write left, as a read does.
                let raw = image.read_device(device.device, device.width).unwrap_or(0);
                changed.push((
                    DataValue::new_at(variant(*kind, raw), now),
                    node.value().node_id.clone(),
                ));
            }
        }
        context.subscriptions.notify_data_change(
            changed
                .iter()
                .map(|(value, id)| (value.clone(), id, AttributeId::Value)),
        );
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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
