//! The test device's object dictionary and an application that backs its DOMAIN.

use std::cell::RefCell;
use std::rc::Rc;

use ecat_core::coe::AbortCode;
use ecat_core::device::Identity;
use ecat_core::dictionary::{
    Bits, Communication, DeviceInfo, Domain, ObjectHooks, UnicodeString, VisibleString,
};
use ecat_embassy::Application;

/// 0x1018.
pub const IDENTITY: Identity = Identity {
    vendor_id: 0xE000_0001,
    product_code: 0x0000_0402,
    revision: 1,
    serial: 0x1234_5678,
};

pub struct Params {
    pub enable: bool,
    pub level: Bits<3>,
    pub gain: u16,
    pub offset: i32,
}

pub struct TestOd {
    pub area: Communication,
    pub error_register: u8,
    pub text: VisibleString<300>,
    pub blob: Domain,
    pub params: Params,
    pub secret: u32,
    pub tuning: u16,
    pub label: UnicodeString<4>,
    pub controlword: u16,
    pub target_position: i32,
}

/// The communication area of the test device.
pub const INFO: DeviceInfo = DeviceInfo {
    device_type: 0x0002_0192,
    name: "ecat test device",
    hardware_version: "1.0",
    software_version: "0.1.0",
    identity: IDENTITY,
};

ecat_core::dictionary! {
    // A test device of the SDO server and SDO Information: no process data, so no PDO
    // assignments.
    minimal TestOd {
        communication(area, INFO);
        0x1001 => var(error_register, RO, "Error register");
        0x2000 => var(text, RW, "Text");
        0x2001 => var(blob, RW, "Blob");
        0x2002 => record(params: Params, "Parameters") {
            1 => enable, RW, "Enable";
            2 => level, RW, "Level";
            3 => gain, RW, "Gain", max = 1000;
            4 => offset, RW, "Offset";
        };
        0x2003 => var(secret, WO, "Secret");
        0x2004 => var(tuning, RW_PREOP, "Tuning");
        0x2005 => var(label, RW, "Label");
        0x6040 => var(controlword, RW | RXPDO, "Controlword");
        0x607A => var(target_position, RW | RXPDO, "Target position", min = -1000, max = 1000);
    }
}

/// The application of the test device: accepts every transition, backs DOMAIN 0x2001 with a
/// byte vector, vetoes writes of 0xDEAD to 0x6040 and logs every write it is told about.
#[derive(Clone, Default)]
pub struct BlobApp {
    pub blob: Rc<RefCell<Vec<u8>>>,
    pub written: Rc<RefCell<Vec<(u16, u8)>>>,
}

impl Application<TestOd> for BlobApp {
    fn object_hooks(&mut self) -> impl ObjectHooks<TestOd> + '_ {
        self.clone()
    }
}

impl ObjectHooks<TestOd> for BlobApp {
    fn before_write(
        &mut self,
        _od: &TestOd,
        index: u16,
        _sub: u8,
        data: &[u8],
    ) -> Result<(), AbortCode> {
        if index == 0x6040 && data == [0xAD, 0xDE] {
            return Err(AbortCode::LOCAL_CONTROL);
        }
        Ok(())
    }

    fn after_write(&mut self, _od: &mut TestOd, index: u16, sub: u8) {
        self.written.borrow_mut().push((index, sub));
    }

    fn domain_size(&mut self, _index: u16, _sub: u8) -> Result<u32, AbortCode> {
        Ok(self.blob.borrow().len() as u32)
    }

    fn domain_read(
        &mut self,
        _index: u16,
        _sub: u8,
        offset: u32,
        out: &mut [u8],
    ) -> Result<usize, AbortCode> {
        let blob = self.blob.borrow();
        let rest = blob.get(offset as usize..).unwrap_or_default();
        let n = rest.len().min(out.len());
        out[..n].copy_from_slice(&rest[..n]);
        Ok(n)
    }

    fn domain_write(
        &mut self,
        _index: u16,
        _sub: u8,
        offset: u32,
        data: &[u8],
        _last: bool,
    ) -> Result<(), AbortCode> {
        let mut blob = self.blob.borrow_mut();
        if offset == 0 {
            blob.clear();
        }
        assert_eq!(blob.len(), offset as usize, "DOMAIN pieces arrive in order");
        blob.extend_from_slice(data);
        Ok(())
    }
}
