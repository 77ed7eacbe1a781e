//! Modbus as a server answers it, apart from any device map: request PDUs
//! decoded with the exceptions the specification names and responses
//! encoded (`pdu`), on Modbus TCP (the MBAP header) or Modbus RTU (`rtu`:
//! serial frames with a CRC, delimited by silence). The soft PLC's map of
//! addresses to devices is the server's (`ladder-serve`).

pub mod pdu;
pub mod rtu;

pub use pdu::{decode, encode, header, Header, HEADER_LEN, MAX_PDU_LEN};
