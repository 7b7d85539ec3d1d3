//! [`dictionary!`](crate::dictionary!): the declaration of a device's object dictionary, and
//! where the features meet. A declaration expands into the dictionary's table
//! ([`dictionary`](crate::dictionary)), the process-image copy and the shape the PDO layout
//! derives from the table ([`pdo`](crate::pdo)), the communication area with its sync parameter
//! records ([`sync_parameters`](crate::sync_parameters)) and the diagnosis history
//! ([`diagnosis`](crate::diagnosis)): the macro sits above them all, so none of them imports
//! another for the declaration's sake.

/// Maps object indices onto the fields of a dictionary struct; see the [module
/// documentation](mod@crate::dictionary) for an example.
///
/// ```text
/// dictionary! {
///     [minimal] Struct {
///         [sync(MODES);]
///         communication(field, DEVICE_INFO [, stored = field]);
///         INDEX => var(field, ACCESS, "Name" [, default = EXPR] [, min = EXPR] [, max = EXPR] [, unit = EXPR]);
///         INDEX => array(field, ACCESS, "Name", "Element name" [, default = …] [, min = …] [, max = …] [, unit = …]);
///         INDEX => record(field: RecordType, "Name") {
///             SUB => field, ACCESS, "Name" [, default = …] [, min = …] [, max = …] [, unit = …];
///         };
///         INDEX => pdo(field, ACCESS, "Name", "Entry name" [, default = …]);
///         0x10F3 => diagnosis(field);
///     }
/// }
/// ```
///
/// `sync(MODES)` (first, optional; a [`SupportedSyncModes`](crate::sync_mode::SupportedSyncModes)
/// constant) states the synchronisation modes the device supports (0x1C32:04):
/// [`ObjectDictionary::SYNC_MODES`](crate::dictionary::ObjectDictionary::SYNC_MODES), free-run
/// and SM-synchronous without it. A device without DC SYNC0 there carries no DC code.
///
/// `communication` (first after `sync`, once) makes the communication area
/// ([`dictionary::communication`](crate::dictionary::communication)) from the
/// [`DeviceInfo`](crate::dictionary::DeviceInfo) constant `DEVICE_INFO` and a
/// [`Communication`](crate::dictionary::Communication) field: 0x1000 device type, 0x1008/0x1009/
/// 0x100A names and versions, 0x1018 identity (initialised from `DEVICE_INFO.identity`, the same
/// constant the SII image and the ESI file are generated from), 0x1C00 SyncManager types
/// ([`STANDARD_KINDS`](crate::sync_manager::STANDARD_KINDS), as the SII and ESI give them), and 0x1C32/0x1C33,
/// SSC's sync parameter records with the entries the stack fills (SI1 sync type: writable in
/// PREOP, default 1 for the outputs, 0x22 for the inputs — the inputs' type follows the
/// outputs' ([`sync_parameters::input_sync_type`](crate::sync_parameters::input_sync_type)), so a value a MainDevice
/// writes there, as TwinCAT and SOEM setups do beside 0x1C32:01, is replaced by the type in
/// effect when the configuration is next refreshed, and one that is no sync type is refused,
/// [`sync_parameters::check_input_sync_write`](crate::sync_parameters::check_input_sync_write); SI2 cycle time
/// writable in PREOP; SI8 get cycle time writable in every state; SI3..SI7, SI9, SI 0x0A..0x0D,
/// 0x20 read-only; SI0 = 0x20). The area's objects are merged with the application's by index
/// at compile time; the application may not declare them itself. With `stored = field` (a
/// [`StoredParameters`](crate::dictionary::parameters::StoredParameters) field) the area also
/// has 0x1010 store parameters and 0x1011 restore default parameters
/// ([`dictionary::parameters`](crate::dictionary::parameters)): the entries whose access has
/// `BACKUP` are what a "save" stores.
///
/// A dictionary is a CoE device's unless it starts with `minimal`: it must have the
/// communication area and the PDO assignments 0x1C12 and 0x1C13 (SOEM's `config_map` reads
/// 0x1C00 and both assignments of every CoE device; an abort there fails the configuration),
/// else it does not compile. `minimal` is for what is no CoE device's dictionary: tests of one
/// feature (the SDO server, the PDO rules) and benchmarks.
///
/// `pdo` declares a PDO mapping (0x1600..0x17FF, 0x1A00..0x1BFF; field type
/// [`PdoMapping<N>`](crate::pdo::PdoMapping)) or assignment object (0x1C12, 0x1C13;
/// [`PdoAssignment<N>`](crate::pdo::PdoAssignment)): SI0 counts the valid entries and follows the
/// PDO configuration write rules of [`crate::pdo`]. Its `default` is a constant expression
/// ([`PdoMapping::mapping`](crate::pdo::PdoMapping::mapping),
/// [`PdoAssignment::assignment`](crate::pdo::PdoAssignment::assignment)): evaluated at compile
/// time, `Default` copies it rather than building it at run time.
///
/// `diagnosis` declares the diagnosis history at 0x10F3 (field type
/// [`DiagnosisHistory<N>`](crate::diagnosis::DiagnosisHistory)): the stack logs its own events
/// into it ([`ObjectDictionary::diagnosis`](crate::dictionary::ObjectDictionary::diagnosis)).
///
/// `ACCESS` is one or more [`Access`](crate::dictionary::Access) constants joined by `|`
/// (`RO`, `RW`, `WO`, `RW_PREOP`, `RW_PREOP_SAFEOP`, `RXPDO`, `TXPDO`, `BACKUP`, `SETTINGS`).
/// Array fields are `[T; N]`; record fields are structs whose fields the entries name. The macro
/// implements [`ObjectDictionary`](crate::dictionary::ObjectDictionary) and `Default` (every field
/// at its declared default, or the type's default), and asserts at compile time that indices and
/// subindices ascend strictly, that only mappable types are PDO-mappable and that PDO mapping and
/// assignment objects are writable in PREOP only:
///
/// ```compile_fail,E0080
/// pub struct Od { a: u8 }
/// ecat_core::dictionary! {
///     Od {
///         0x2000 => var(a, RO, "A"); // no communication area: does not compile
///     }
/// }
/// ```
///
/// ```compile_fail,E0080
/// use ecat_core::dictionary::{Communication, DeviceInfo};
/// # use ecat_core::device::Identity;
/// # const INFO: DeviceInfo = DeviceInfo { device_type: 0, name: "a", hardware_version: "1",
/// #     software_version: "1", identity: Identity { vendor_id: 1, product_code: 1, revision: 1, serial: 1 } };
/// pub struct Od { area: Communication, a: u8 }
/// ecat_core::dictionary! {
///     Od {
///         communication(area, INFO);
///         0x2000 => var(a, RO, "A"); // no 0x1C12/0x1C13: does not compile
///     }
/// }
/// ```
///
/// ```compile_fail,E0080
/// use ecat_core::dictionary::{Communication, DeviceInfo};
/// # use ecat_core::device::Identity;
/// # const INFO: DeviceInfo = DeviceInfo { device_type: 0, name: "a", hardware_version: "1",
/// #     software_version: "1", identity: Identity { vendor_id: 1, product_code: 1, revision: 1, serial: 1 } };
/// pub struct Od { area: Communication, t: u32 }
/// ecat_core::dictionary! {
///     minimal Od {
///         communication(area, INFO);
///         0x1000 => var(t, RO, "Device type"); // the area's: does not compile
///     }
/// }
/// ```
///
/// ```
/// // The same without the mistake compiles: `minimal`, no assignments needed.
/// use ecat_core::dictionary::{Communication, DeviceInfo};
/// # use ecat_core::device::Identity;
/// # const INFO: DeviceInfo = DeviceInfo { device_type: 0, name: "a", hardware_version: "1",
/// #     software_version: "1", identity: Identity { vendor_id: 1, product_code: 1, revision: 1, serial: 1 } };
/// pub struct Od { area: Communication, t: u32 }
/// ecat_core::dictionary! {
///     minimal Od {
///         communication(area, INFO);
///         0x2000 => var(t, RO, "Value");
///     }
/// }
/// ```
///
/// The other checks hold for every dictionary (the examples are `minimal` to show one rule
/// each):
///
/// ```compile_fail
/// pub struct Od { a: u8, b: u8 }
/// ecat_core::dictionary! {
///     minimal Od {
///         0x2001 => var(a, RO, "A");
///         0x2000 => var(b, RO, "B"); // not ascending: does not compile
///     }
/// }
/// ```
///
/// ```compile_fail
/// use ecat_core::dictionary::VisibleString;
/// pub struct Od { name: VisibleString<8> }
/// ecat_core::dictionary! {
///     minimal Od {
///         0x2000 => var(name, RW | TXPDO, "Name"); // a string is not PDO-mappable
///     }
/// }
/// ```
///
/// ```compile_fail
/// pub struct Od { a: u8 }
/// ecat_core::dictionary! {
///     minimal Od {
///         0x2000 => var(a, RO, "A", min = 300); // 300 is not a u8
///     }
/// }
/// ```
///
/// ```compile_fail
/// use ecat_core::pdo::PdoAssignment;
/// pub struct Od { assign: PdoAssignment<2> }
/// ecat_core::dictionary! {
///     minimal Od {
///         0x1C12 => pdo(assign, RW, "SM2 assignment", "PDO"); // writable in OP: does not compile
///     }
/// }
/// ```
#[macro_export]
macro_rules! dictionary {
    (minimal $dict:ident { $($body:tt)* }) => {
        $crate::__ecat_dictionary!(minimal, [], $dict { $($body)* });
    };
    ($dict:ident { $($body:tt)* }) => {
        $crate::__ecat_dictionary!(coe, [], $dict { $($body)* });
    };
}

/// [`dictionary!`] with or without the communication area: the table of objects and the
/// fields' defaults, then the common part.
#[doc(hidden)]
#[macro_export]
macro_rules! __ecat_dictionary {
    ($mode:ident, [], $dict:ident { sync ( $sync:expr ) ; $($body:tt)* }) => {
        $crate::__ecat_dictionary!($mode, [sync = $sync;], $dict { $($body)* });
    };
    ($mode:ident, [$($sync:tt)*], $dict:ident { communication ( $area:ident, $info:path ) ; $($items:tt)* }) => {
        $crate::__ecat_impl!($mode, $dict, {
            const APPLICATION: &[$crate::dictionary::Declaration<$dict>] = $crate::__ecat_objects!($dict, $($items)*);
            const AREA: [$crate::dictionary::Declaration<$dict>; 8] = $crate::__ecat_communication!($dict, $area, $info);
            const _: () = assert!(
                $crate::dictionary::communication::leaves_communication_area(APPLICATION),
                "0x1000, 0x1008, 0x1009, 0x100A, 0x1018, 0x1C00, 0x1C32 and 0x1C33 come from `communication`: do not declare them"
            );
            &$crate::dictionary::communication::merge::<$dict, &'static str, { APPLICATION.len() + 8 }>(&AREA, APPLICATION)
        }, [$crate::__ecat_area_limits!($info), $crate::dictionary::communication::DECLARED, $crate::sync_parameters::DECLARED], [$area: const { $crate::dictionary::Communication::new(&$info) },] communication = $area; $($sync)* $($items)*);
    };
    ($mode:ident, [$($sync:tt)*], $dict:ident { communication ( $area:ident, $info:path, stored = $stored:ident ) ; $($items:tt)* }) => {
        $crate::__ecat_impl!($mode, $dict, {
            const APPLICATION: &[$crate::dictionary::Declaration<$dict>] = $crate::__ecat_objects!($dict, $($items)*);
            const AREA: &[$crate::dictionary::Declaration<$dict>] = &$crate::__ecat_communication!($dict, $area, $info);
            const STORAGE: [$crate::dictionary::Declaration<$dict>; 2] = $crate::__ecat_storage!($dict, $stored);
            const _: () = assert!(
                $crate::dictionary::communication::leaves_communication_area(APPLICATION)
                    && $crate::dictionary::parameters::leaves_storage(APPLICATION),
                "the communication area's objects (with 0x1010/0x1011 under `stored`) come from `communication`: do not declare them"
            );
            const BASE: [$crate::dictionary::Declaration<$dict>; APPLICATION.len() + AREA.len()] =
                $crate::dictionary::communication::merge::<$dict, &'static str, { APPLICATION.len() + AREA.len() }>(AREA, APPLICATION);
            &$crate::dictionary::communication::merge::<$dict, &'static str, { BASE.len() + 2 }>(&STORAGE, &BASE)
        }, [$crate::__ecat_area_limits!($info), $crate::dictionary::communication::DECLARED, $crate::sync_parameters::DECLARED], [$area: const { $crate::dictionary::Communication::new(&$info) }, $stored: $crate::dictionary::parameters::StoredParameters::new(),]
        communication = $area; stored = $stored; $($sync)* $($items)*);
    };
    ($mode:ident, [$($sync:tt)*], $dict:ident { $($items:tt)* }) => {
        $crate::__ecat_impl!($mode, $dict, $crate::__ecat_objects!($dict, $($items)*), [], [] $($sync)* $($items)*);
    };
}

/// The table of an application's objects.
#[doc(hidden)]
#[macro_export]
macro_rules! __ecat_objects {
    ($dict:ident, $( $index:literal => $kind:ident ( $field:ident $($spec:tt)* ) $({ $($subs:tt)* })? ; )*) => {
        &[ $( $crate::__ecat_object!($dict, $index, $kind ( $field $($spec)* ) $({ $($subs)* })?), )* ]
    };
}

/// The implementation of [`ObjectDictionary`](crate::dictionary::ObjectDictionary) and `Default`
/// for the table `$objects`, and the `const` checks (`coe`: also the mandatory objects).
#[doc(hidden)]
#[macro_export]
macro_rules! __ecat_impl {
    ($mode:ident, $dict:ident, $objects:expr, [$($area_limits:expr),*], [$($area:tt)*] $(communication = $communication:ident;)?
     $(stored = $stored:ident;)?
     $(sync = $sync:expr;)?
     $( $index:literal => $kind:ident ( $field:ident $($spec:tt)* ) $({ $($subs:tt)* })? ; )*) => {
        impl $crate::dictionary::ObjectDictionary for $dict {
            const DECLARATION: &'static [$crate::dictionary::Declaration<Self>] = $objects;

            $( const SYNC_MODES: $crate::sync_mode::SupportedSyncModes = $sync; )?

            const NAMES: &'static str = {
                const DECLARED: &[$crate::dictionary::Declaration<$dict>] =
                    <$dict as $crate::dictionary::ObjectDictionary>::DECLARATION;
                const NAMES: [&str; $crate::dictionary::compact::name_count(DECLARED)] =
                    $crate::dictionary::compact::names(DECLARED);
                const TABLE: &[u8] =
                    &$crate::dictionary::compact::table::<{ $crate::dictionary::compact::table_len(&NAMES) }>(&NAMES);
                $crate::dictionary::compact::text(TABLE)
            };

            const OBJECTS: &'static [$crate::dictionary::Object<Self>] = {
                const DECLARED: &[$crate::dictionary::Declaration<$dict>] =
                    <$dict as $crate::dictionary::ObjectDictionary>::DECLARATION;
                const NAMES: [&str; $crate::dictionary::compact::name_count(DECLARED)] =
                    $crate::dictionary::compact::names(DECLARED);
                const AT: [$crate::dictionary::Name; NAMES.len()] = $crate::dictionary::compact::refs(&NAMES);
                const ENTRIES: &[$crate::dictionary::EntryInfo] =
                    &$crate::dictionary::compact::entries::<$dict, { $crate::dictionary::compact::entries_len(DECLARED) }>(DECLARED, &AT);
                &$crate::dictionary::compact::objects::<$dict, { DECLARED.len() }>(DECLARED, &AT, ENTRIES)
            };

            const INDICES: &'static [u16] = $crate::coe::sdo_info::all_indices(
                <$dict as $crate::dictionary::ObjectDictionary>::OBJECTS,
                <$dict as $crate::dictionary::ObjectDictionary>::OD_LISTS,
            );

            const LIMITS: &'static [u8] = {
                const GROUPS: &[&[$crate::dictionary::limits::Declared]] = &[
                    $($area_limits,)*
                    $( $crate::__ecat_declared!($dict, $index, $kind ( $field $($spec)* ) $({ $($subs)* })?), )*
                ];
                &$crate::dictionary::limits::pack::<{ $crate::dictionary::limits::packed_len(GROUPS) }>(GROUPS)
            };

            $(
                fn communication(&mut self) -> Option<&mut $crate::dictionary::Communication> {
                    Some(&mut self.$communication)
                }
            )?

            $(
                fn stored_parameters(&mut self) -> Option<&mut $crate::dictionary::parameters::StoredParameters> {
                    Some(&mut self.$stored)
                }
            )?

            type Mappable = $crate::dictionary::Len<{ $crate::pdo::layout::mappable_entries(
                <$dict as $crate::dictionary::ObjectDictionary>::OBJECTS,
            ) }>;

            type Repeatable = $crate::dictionary::Len<{ $crate::pdo::layout::repeat_room(
                <$dict as $crate::dictionary::ObjectDictionary>::OBJECTS,
            ) }>;

            type Download = $crate::dictionary::Len<{ $crate::coe::sdo::largest_download(
                <$dict as $crate::dictionary::ObjectDictionary>::OBJECTS,
            ) }>;

            const MAPPABLE: &'static [u32] = &$crate::pdo::layout::mappable_keys::<
                $dict,
                { $crate::pdo::layout::mappable_entries(<$dict as $crate::dictionary::ObjectDictionary>::OBJECTS) },
            >(<$dict as $crate::dictionary::ObjectDictionary>::OBJECTS);

            const OD_LISTS: &'static [u16] = &$crate::coe::sdo_info::od_lists::<
                $dict,
                { $crate::coe::sdo_info::od_lists_len(<$dict as $crate::dictionary::ObjectDictionary>::OBJECTS) },
            >(<$dict as $crate::dictionary::ObjectDictionary>::OBJECTS);

            #[allow(unused_variables)] // a dictionary without RxPDO-mappable entries
            fn unpack_mapped(&mut self, offsets: &$crate::dictionary::PerMappable<Self, u16>, image: &[u8]) {
                let od = self;
                $( $crate::__ecat_mapped!(unpack, $dict, od, offsets, image, $index, $kind ( $field $($spec)* ) $({ $($subs)* })?); )*
            }

            #[allow(unused_variables)] // a dictionary without TxPDO-mappable entries
            fn pack_mapped(&self, offsets: &$crate::dictionary::PerMappable<Self, u16>, image: &mut [u8]) {
                let od = self;
                $( $crate::__ecat_mapped!(pack, $dict, od, offsets, image, $index, $kind ( $field $($spec)* ) $({ $($subs)* })?); )*
            }

            #[allow(unreachable_code, unused_variables)] // with a diagnosis history, without
            fn diagnosis(&mut self) -> Option<$crate::diagnosis::History<'_>> {
                let od = self;
                $( $crate::__ecat_diagnosis!(od, $kind ( $field $($spec)* ) $({ $($subs)* })?); )*
                None
            }
        }

        const _: () = {
            let objects = <$dict as $crate::dictionary::ObjectDictionary>::OBJECTS;
            assert!(
                $crate::dictionary::is_well_formed(objects),
                "object indices and record subindices must ascend strictly"
            );
            assert!(
                $crate::dictionary::mappable_types_only(objects),
                "only numeric and bit types may be PDO-mappable"
            );
            assert!(
                $crate::pdo::configuration_preop_only(objects),
                "PDO mapping and assignment objects may be writable in PREOP only"
            );
            $crate::__ecat_mandatory!($mode, objects);
        };

        impl ::core::default::Default for $dict {
            fn default() -> Self {
                Self {
                    $($area)*
                    $( $field: $crate::__ecat_default!($kind ( $field $($spec)* ) $({ $($subs)* })?), )*
                }
            }
        }
    };
}

/// The mandatory objects of a CoE device (`coe`), none for a `minimal` dictionary.
#[doc(hidden)]
#[macro_export]
macro_rules! __ecat_mandatory {
    (minimal, $objects:ident) => {};
    (coe, $objects:ident) => {
        assert!(
            $crate::dictionary::communication::has_communication_area($objects),
            "a CoE device's dictionary needs the communication area (0x1000, 0x1008, 0x1009, 0x100A, 0x1018, 0x1C00, 0x1C32, 0x1C33): declare `communication(field, DEVICE_INFO);` first, or start with `minimal` a dictionary that is no CoE device's"
        );
        assert!(
            $crate::dictionary::communication::has_pdo_assignments($objects),
            "a CoE device's dictionary needs 0x1C12 and 0x1C13 (SM2/SM3 PDO assignment; `pdo` items, empty for a direction without process data): MainDevices read both"
        );
    };
}

/// The objects of the communication area, ascending: thin calls into the shared code of
/// [`dictionary::communication`](crate::dictionary::communication) and
/// [`SyncParameters`](crate::sync_parameters::SyncParameters) with the place of the field.
#[doc(hidden)]
#[macro_export]
macro_rules! __ecat_communication {
    ($dict:ident, $area:ident, $info:path) => {
        [
            $crate::__ecat_constant!(
                $dict,
                0x1000,
                $crate::dictionary::communication::DEVICE_TYPE
            ),
            $crate::__ecat_text!($dict, 0x1008, "Manufacturer device name", $info.name),
            $crate::__ecat_text!(
                $dict,
                0x1009,
                "Manufacturer hardware version",
                $info.hardware_version
            ),
            $crate::__ecat_text!(
                $dict,
                0x100A,
                "Manufacturer software version",
                $info.software_version
            ),
            $crate::dictionary::Declaration::<$dict> {
                info: $crate::dictionary::communication::IDENTITY,
                read: |d: &$dict, at: $crate::dictionary::At, out: &mut [u8]| {
                    $crate::dictionary::communication::read_identity(&d.$area.identity, at, out)
                },
                write: $crate::dictionary::communication::read_only::<$dict>,
            },
            $crate::dictionary::Declaration::<$dict> {
                info: $crate::dictionary::communication::SM_TYPES,
                read: |_: &$dict, at: $crate::dictionary::At, out: &mut [u8]| {
                    $crate::dictionary::communication::read_declared::<$dict>(
                        $crate::dictionary::communication::SM_TYPES.index,
                        at,
                        out,
                    )
                },
                write: $crate::dictionary::communication::read_only::<$dict>,
            },
            $crate::__ecat_sync_parameters!(
                $dict,
                0x1C32,
                $area.outputs,
                "SM output parameter",
                write
            ),
            $crate::__ecat_sync_parameters!(
                $dict,
                0x1C33,
                $area.inputs,
                "SM input parameter",
                write_input
            ),
        ]
    };
}

/// The declared values of the communication area that come from the device's `DeviceInfo`
/// `$info`: the constants' (0x1000, 0x1008, 0x1009, 0x100A) and the identity's (0x1018:01..04)
/// defaults, their values.
#[doc(hidden)]
#[macro_export]
macro_rules! __ecat_area_limits {
    ($info:path) => {
        &[
            $crate::__ecat_area_limit!(0x1000, 0, &$info.device_type.to_le_bytes()),
            $crate::__ecat_area_limit!(0x1008, 0, $info.name.as_bytes()),
            $crate::__ecat_area_limit!(0x1009, 0, $info.hardware_version.as_bytes()),
            $crate::__ecat_area_limit!(0x100A, 0, $info.software_version.as_bytes()),
            $crate::__ecat_area_limit!(0x1018, 1, &$info.identity.vendor_id.to_le_bytes()),
            $crate::__ecat_area_limit!(0x1018, 2, &$info.identity.product_code.to_le_bytes()),
            $crate::__ecat_area_limit!(0x1018, 3, &$info.identity.revision.to_le_bytes()),
            $crate::__ecat_area_limit!(0x1018, 4, &$info.identity.serial.to_le_bytes()),
        ]
    };
}

/// One default of the communication area.
#[doc(hidden)]
#[macro_export]
macro_rules! __ecat_area_limit {
    ($index:literal, $sub:literal, $bytes:expr) => {
        $crate::dictionary::limits::Declared::new(
            $index,
            $sub,
            $crate::dictionary::Limit::Default,
            $bytes,
        )
    };
}

/// The declared values of one object ([`dictionary::limits`](crate::dictionary::limits)).
#[doc(hidden)]
#[macro_export]
macro_rules! __ecat_declared {
    ($dict:ident, $index:literal, var (
        $field:ident, $($acc:ident)|+, $name:literal
        $(, default = $default:expr)? $(, min = $min:expr)? $(, max = $max:expr)? $(, unit = $unit:expr)?
    )) => {
        &[
            $( $crate::__ecat_value!($index, 0, Default, of(|d: &$dict| &d.$field, $default)), )?
            $( $crate::__ecat_value!($index, 0, Min, of(|d: &$dict| &d.$field, $min)), )?
            $( $crate::__ecat_value!($index, 0, Max, of(|d: &$dict| &d.$field, $max)), )?
            $( $crate::__ecat_value!($index, 0, Unit, unit($unit)), )?
        ]
    };
    ($dict:ident, $index:literal, array (
        $field:ident, $($acc:ident)|+, $name:literal, $element:literal
        $(, default = $default:expr)? $(, min = $min:expr)? $(, max = $max:expr)? $(, unit = $unit:expr)?
    )) => {
        &[
            $( $crate::__ecat_value!($index, 1, Default, element(|d: &$dict| &d.$field, $default)).every_element(), )?
            $( $crate::__ecat_value!($index, 1, Min, element(|d: &$dict| &d.$field, $min)).every_element(), )?
            $( $crate::__ecat_value!($index, 1, Max, element(|d: &$dict| &d.$field, $max)).every_element(), )?
            $( $crate::__ecat_value!($index, 1, Unit, unit($unit)).every_element(), )?
        ]
    };
    ($dict:ident, $index:literal, record ( $field:ident : $record:ident, $name:literal ) {
        $( $sub:literal => $sfield:ident, $($acc:ident)|+, $sname:literal
           $(, default = $default:expr)? $(, min = $min:expr)? $(, max = $max:expr)? $(, unit = $unit:expr)? ; )+
    }) => {
        &[ $(
            $( $crate::__ecat_value!($index, $sub, Default, of(|d: &$dict| &d.$field.$sfield, $default)), )?
            $( $crate::__ecat_value!($index, $sub, Min, of(|d: &$dict| &d.$field.$sfield, $min)), )?
            $( $crate::__ecat_value!($index, $sub, Max, of(|d: &$dict| &d.$field.$sfield, $max)), )?
            $( $crate::__ecat_value!($index, $sub, Unit, unit($unit)), )?
        )+ ]
    };
    // PDO configuration objects and the diagnosis history declare none.
    ($dict:ident, $index:literal, $($other:tt)*) => {
        &[]
    };
}

/// One declared value, encoded at compile time by its type's `encode`.
#[doc(hidden)]
#[macro_export]
macro_rules! __ecat_value {
    ($index:literal, $sub:literal, $which:ident, $how:ident ( $($args:tt)* )) => {
        $crate::dictionary::limits::Declared::new(
            $index,
            $sub,
            $crate::dictionary::Limit::$which,
            $crate::dictionary::limits::Bytes::as_slice(
                &$crate::dictionary::limits::$how($($args)*).encode(),
            ),
        )
    };
}

/// A text constant of the communication area (0x1008, 0x1009, 0x100A).
#[doc(hidden)]
#[macro_export]
macro_rules! __ecat_text {
    ($dict:ident, $index:literal, $name:literal, $text:expr) => {
        $crate::__ecat_constant!(
            $dict,
            $index,
            $crate::dictionary::ObjectInfo {
                index: $index,
                code: $crate::dictionary::ObjectCode::Var,
                name: $name,
                max_sub: 0,
                entries: &[$crate::dictionary::communication::text_entry($name, $text)],
            }
        )
    };
}

/// A constant VAR of the communication area (0x1000 and the texts): described by `$info`,
/// read-only, declared as its own default — and read from there: its value is the bytes of its
/// default's record in the dictionary's `LIMITS`, in flash once, read by the shared
/// `read_declared` with the index as its key.
#[doc(hidden)]
#[macro_export]
macro_rules! __ecat_constant {
    ($dict:ident, $index:literal, $info:expr) => {
        $crate::dictionary::Declaration::<$dict> {
            info: $info,
            read: |_: &$dict, at: $crate::dictionary::At, out: &mut [u8]| {
                $crate::dictionary::communication::read_declared::<$dict>(
                    const {
                        // Its value is its default: the record must exist (a build error else).
                        $crate::dictionary::limits::default_of(
                            <$dict as $crate::dictionary::ObjectDictionary>::LIMITS,
                            $index,
                        );
                        $index
                    },
                    at,
                    out,
                )
            },
            write: $crate::dictionary::communication::read_only::<$dict>,
        }
    };
}

/// One `Object<D>` of a dictionary table.
#[doc(hidden)]
#[macro_export]
macro_rules! __ecat_object {
    ($dict:ident, $index:literal, var (
        $field:ident, $($acc:ident)|+, $name:literal
        $(, default = $default:expr)? $(, min = $min:expr)? $(, max = $max:expr)? $(, unit = $unit:expr)?
    )) => {
        $crate::dictionary::Declaration::<$dict> {
            info: $crate::dictionary::ObjectInfo {
                index: $index,
                code: $crate::dictionary::ObjectCode::Var,
                name: $name,
                max_sub: 0,
                entries: &[$crate::__ecat_entry!(
                    0, $name, data_type_of, bit_len_of, |d: &$dict| &d.$field,
                    [$($acc)|+], [$($unit)?], [$($default)?; $($min)?; $($max)?]
                )],
            },
            read: |d: &$dict, at: $crate::dictionary::At, out: &mut [u8]| {
                $crate::dictionary::read_var(&d.$field, at, out)
            },
            write: $crate::__ecat_write!($dict, [$($acc)|+], |d: &mut $dict, sub: u8, data: &[u8]| {
                $crate::dictionary::write_var(
                    &mut d.$field, sub, data, $crate::__ecat_some!($($min)?), $crate::__ecat_some!($($max)?),
                )
            }),
        }
    };
    ($dict:ident, $index:literal, array (
        $field:ident, $($acc:ident)|+, $name:literal, $element:literal
        $(, default = $default:expr)? $(, min = $min:expr)? $(, max = $max:expr)? $(, unit = $unit:expr)?
    )) => {
        $crate::dictionary::Declaration::<$dict> {
            info: $crate::dictionary::ObjectInfo {
                index: $index,
                code: $crate::dictionary::ObjectCode::Array,
                name: $name,
                max_sub: $crate::dictionary::array_len_of(|d: &$dict| &d.$field),
                entries: &[
                    $crate::dictionary::EntryInfo::subindex_count("Number of entries"),
                    $crate::__ecat_entry!(
                        1, $element, element_type_of, element_bit_len_of, |d: &$dict| &d.$field,
                        [$($acc)|+], [$($unit)?], [$($default)?; $($min)?; $($max)?]
                    ),
                ],
            },
            read: |d: &$dict, at: $crate::dictionary::At, out: &mut [u8]| {
                $crate::dictionary::read_element(&d.$field, at, out)
            },
            write: $crate::__ecat_write!($dict, [$($acc)|+], |d: &mut $dict, sub: u8, data: &[u8]| {
                $crate::dictionary::write_element(
                    &mut d.$field, sub, data, $crate::__ecat_some!($($min)?), $crate::__ecat_some!($($max)?),
                )
            }),
        }
    };
    ($dict:ident, $index:literal, pdo (
        $field:ident, $($acc:ident)|+, $name:literal, $element:literal $(, default = $default:expr)?
    )) => {
        $crate::dictionary::Declaration::<$dict> {
            info: $crate::dictionary::ObjectInfo {
                index: $index,
                code: $crate::pdo::object_code($index),
                name: $name,
                max_sub: $crate::dictionary::array_len_of(|d: &$dict| &d.$field.items),
                entries: &[
                    $crate::dictionary::EntryInfo {
                        access: $crate::__ecat_access!($($acc)|+),
                        ..$crate::dictionary::EntryInfo::subindex_count("Number of entries")
                    },
                    $crate::__ecat_entry!(
                        1, $element, element_type_of, element_bit_len_of, |d: &$dict| &d.$field.items,
                        [$($acc)|+], [], [;;]
                    ),
                ],
            },
            read: |d: &$dict, at: $crate::dictionary::At, out: &mut [u8]| {
                d.$field.read(at, out)
            },
            write: $crate::__ecat_write!($dict, [$($acc)|+], |d: &mut $dict, sub: u8, data: &[u8]| {
                d.$field.write::<$dict>(sub, data, $index)
            }),
        }
    };
    ($dict:ident, $index:literal, diagnosis ( $field:ident )) => {
        $crate::dictionary::Declaration::<$dict> {
            info: $crate::dictionary::ObjectInfo {
                index: $crate::diagnosis::index($index),
                max_sub: $crate::diagnosis::max_sub_of(|d: &$dict| &d.$field),
                ..$crate::diagnosis::OBJECT
            },
            read: |d: &$dict, at: $crate::dictionary::At, out: &mut [u8]| {
                d.$field.log.read(&d.$field.messages, at, out)
            },
            write: |d: &mut $dict, sub: u8, data: &[u8]| {
                let field = &mut d.$field;
                field.log.write(&field.messages, sub, data)
            },
        }
    };
    ($dict:ident, $index:literal, record ( $field:ident : $record:ident, $name:literal ) {
        $( $sub:literal => $sfield:ident, $($acc:ident)|+, $sname:literal
           $(, default = $default:expr)? $(, min = $min:expr)? $(, max = $max:expr)? $(, unit = $unit:expr)? ; )+
    }) => {
        $crate::dictionary::Declaration::<$dict> {
            info: $crate::dictionary::ObjectInfo {
                index: $index,
                code: $crate::dictionary::ObjectCode::Record,
                name: $name,
                max_sub: $crate::dictionary::last_sub(&[$($sub),+]),
                entries: &[
                    $crate::dictionary::EntryInfo::subindex_count("Highest sub-index supported"),
                    $( $crate::__ecat_entry!(
                        $sub, $sname, data_type_of, bit_len_of, |d: &$dict| &d.$field.$sfield,
                        [$($acc)|+], [$($unit)?], [$($default)?; $($min)?; $($max)?]
                    ), )+
                ],
            },
            read: |d: &$dict, at: $crate::dictionary::At, out: &mut [u8]| match at.sub() {
                0 => Ok($crate::dictionary::read_value(&$crate::dictionary::last_sub(&[$($sub),+]), at.offset(), out)),
                $( $sub => Ok($crate::dictionary::read_value(&d.$field.$sfield, at.offset(), out)), )+
                _ => Err($crate::abort::AbortCode::NO_SUBINDEX),
            },
            write: |d: &mut $dict, sub: u8, data: &[u8]| match sub {
                0 => Err($crate::abort::AbortCode::READ_ONLY),
                $( $sub => $crate::dictionary::write_value(
                    &mut d.$field.$sfield, data, $crate::__ecat_some!($($min)?), $crate::__ecat_some!($($max)?),
                ), )+
                _ => Err($crate::abort::AbortCode::NO_SUBINDEX),
            },
        }
    };
}

/// 0x1010 and 0x1011 ([`dictionary::parameters`](crate::dictionary::parameters)) over the
/// [`StoredParameters`](crate::dictionary::parameters::StoredParameters) field `$stored`.
#[doc(hidden)]
#[macro_export]
macro_rules! __ecat_storage {
    ($dict:ident, $stored:ident) => {
        [
            $crate::__ecat_storage!($dict, $stored, STORE, Save),
            $crate::__ecat_storage!($dict, $stored, RESTORE, RestoreDefaults),
        ]
    };
    ($dict:ident, $stored:ident, $info:ident, $command:ident) => {
        $crate::dictionary::Declaration::<$dict> {
            info: $crate::dictionary::parameters::$info,
            read: |_: &$dict, at: $crate::dictionary::At, out: &mut [u8]| {
                $crate::dictionary::parameters::StoredParameters::read(at, out)
            },
            write: |d: &mut $dict, sub: u8, data: &[u8]| {
                d.$stored
                    .write($crate::dictionary::parameters::Command::$command, sub, data)
            },
        }
    };
}

/// The process-data copy of one object's mappable fields, `unpack` (RxPDO-mappable entries) or
/// `pack` (TxPDO-mappable): see [`pdo::image`](crate::pdo::image).
#[doc(hidden)]
#[macro_export]
macro_rules! __ecat_mapped {
    ($mode:ident, $dict:ident, $od:ident, $offsets:ident, $image:ident, $index:literal,
     var ( $field:ident, $($acc:ident)|+, $name:literal $($rest:tt)* )) => {
        $crate::__ecat_mapped_field!($mode, $dict, $od.$field, $offsets, $image, $index, 0, $($acc)|+);
    };
    ($mode:ident, $dict:ident, $od:ident, $offsets:ident, $image:ident, $index:literal,
     array ( $field:ident, $($acc:ident)|+, $name:literal, $element:literal $($rest:tt)* )) => {
        $crate::__ecat_mapped_field!($mode, $dict, $od.$field, $offsets, $image, $index, 1, $($acc)|+);
    };
    ($mode:ident, $dict:ident, $od:ident, $offsets:ident, $image:ident, $index:literal,
     record ( $field:ident : $record:ident, $name:literal ) {
        $( $sub:literal => $sfield:ident, $($acc:ident)|+, $sname:literal $(, $key:ident = $value:expr)* ; )+
    }) => {
        $( $crate::__ecat_mapped_field!($mode, $dict, $od.$field.$sfield, $offsets, $image, $index, $sub, $($acc)|+); )+
    };
    // PDO mapping/assignment, identity and sync parameter objects are never mappable.
    ($mode:ident, $dict:ident, $od:ident, $offsets:ident, $image:ident, $index:literal, $($other:tt)*) => {};
}

/// One mappable field's copy: `unpack` when its access allows RxPDO mapping, `pack` when it
/// allows TxPDO mapping; `$sub` is the subindex of its (first) entry.
#[doc(hidden)]
#[macro_export]
macro_rules! __ecat_mapped_field {
    (unpack, $dict:ident, $($place:ident).+, $offsets:ident, $image:ident, $index:literal, $sub:literal, $($acc:ident)|+) => {
        if let (true, Some(first)) = $crate::__ecat_entry_number!($dict, $index, $sub, rxpdo, $($acc)|+) {
            $crate::pdo::image::Mapped::unpack(&mut $($place).+, $image, $offsets, first);
        }
    };
    (pack, $dict:ident, $($place:ident).+, $offsets:ident, $image:ident, $index:literal, $sub:literal, $($acc:ident)|+) => {
        if let (true, Some(first)) = $crate::__ecat_entry_number!($dict, $index, $sub, txpdo, $($acc)|+) {
            $crate::pdo::image::Mapped::pack(&$($place).+, $image, $offsets, first);
        }
    };
}

/// `(whether the access allows the direction, the entry number)`, both constants.
#[doc(hidden)]
#[macro_export]
macro_rules! __ecat_entry_number {
    ($dict:ident, $index:literal, $sub:literal, $direction:ident, $($acc:ident)|+) => {
        const {
            (
                $crate::__ecat_access!($($acc)|+).$direction(),
                $crate::pdo::layout::number::<$dict>($index, $sub),
            )
        }
    };
}

/// The diagnosis history of a dictionary: `diagnosis` returns it, the other items nothing.
#[doc(hidden)]
#[macro_export]
macro_rules! __ecat_diagnosis {
    ($od:ident, diagnosis ( $field:ident )) => {
        return Some($od.$field.history());
    };
    ($od:ident, $($other:tt)*) => {};
}

/// The default value of one field.
#[doc(hidden)]
#[macro_export]
macro_rules! __ecat_default {
    (var ( $field:ident, $($acc:ident)|+, $name:literal
        $(, default = $default:expr)? $(, min = $min:expr)? $(, max = $max:expr)? $(, unit = $unit:expr)? )) => {
        $crate::__ecat_or!(::core::default::Default::default() $(, $default)?)
    };
    (array ( $field:ident, $($acc:ident)|+, $name:literal, $element:literal
        $(, default = $default:expr)? $(, min = $min:expr)? $(, max = $max:expr)? $(, unit = $unit:expr)? )) => {
        $crate::dictionary::filled($crate::__ecat_or!(::core::default::Default::default() $(, $default)?))
    };
    (pdo ( $field:ident, $($acc:ident)|+, $name:literal, $element:literal $(, default = $default:expr)? )) => {
        $crate::__ecat_or!(::core::default::Default::default() $(, const { $default })?)
    };
    (diagnosis ( $field:ident )) => {
        $crate::diagnosis::DiagnosisHistory::new()
    };
    (record ( $field:ident : $record:ident, $name:literal ) {
        $( $sub:literal => $sfield:ident, $($acc:ident)|+, $sname:literal
           $(, default = $default:expr)? $(, min = $min:expr)? $(, max = $max:expr)? $(, unit = $unit:expr)? ; )+
    }) => {
        $record { $( $sfield: $crate::__ecat_or!(::core::default::Default::default() $(, $default)?), )+ }
    };
}

/// The record of a sync manager parameter object (0x1C32 outputs, 0x1C33 inputs; ETG.1000.6
/// Table 74): the standard entries (`sync_parameters::PARAMETER_ENTRIES`),
/// read and written by the non-generic [`SyncParameters`](crate::sync_parameters::SyncParameters) methods
/// every dictionary shares (`$write`: `write`, or `write_input` for 0x1C33).
#[doc(hidden)]
#[macro_export]
macro_rules! __ecat_sync_parameters {
    ($dict:ident, $index:literal, $($place:ident).+, $name:literal, $write:ident) => {
        $crate::dictionary::Declaration::<$dict> {
            info: $crate::dictionary::ObjectInfo {
                index: $index,
                code: $crate::dictionary::ObjectCode::Record,
                name: $name,
                max_sub: $crate::sync_parameters::SyncParameters::MAX_SUB,
                entries: $crate::sync_parameters::PARAMETER_ENTRIES,
            },
            read: |d: &$dict, at: $crate::dictionary::At, out: &mut [u8]| d.$($place).+.read(at, out),
            write: |d: &mut $dict, sub: u8, data: &[u8]| d.$($place).+.$write(sub, data),
        }
    };
}

/// An object's write: `$write` when its entries are ever written
/// ([`Access::is_written`](crate::dictionary::Access::is_written)), the shared refusal
/// otherwise — so that a dictionary carries no decoding, range or PDO configuration checks for
/// values no one writes (a fixed PDO configuration, read-only inputs).
#[doc(hidden)]
#[macro_export]
macro_rules! __ecat_write {
    ($dict:ident, [$($acc:ident)|+], $write:expr) => {
        if $crate::__ecat_access!($($acc)|+).is_written() {
            $write
        } else {
            $crate::dictionary::communication::read_only::<$dict>
        }
    };
}

/// `ACCESS | ACCESS` as a `const` [`Access`](crate::dictionary::Access).
#[doc(hidden)]
#[macro_export]
macro_rules! __ecat_access {
    ($($acc:ident)|+) => {
        $crate::dictionary::Access(0 $(| $crate::dictionary::Access::$acc.0)+)
    };
}

/// The last of its arguments.
#[doc(hidden)]
#[macro_export]
macro_rules! __ecat_or {
    ($fallback:expr) => {
        $fallback
    };
    ($fallback:expr, $value:expr) => {
        $value
    };
}

/// One `EntryInfo`: its type and bit length from the field `get` reaches (through `type_of` and
/// `bits_of`, e.g. `data_type_of`/`bit_len_of` or their `element_` forms for arrays), its access,
/// unit and declared limits.
#[doc(hidden)]
#[macro_export]
macro_rules! __ecat_entry {
    ($sub:expr, $name:expr, $type_of:ident, $bits_of:ident, $get:expr,
     [$($acc:ident)|+], [$($unit:expr)?], [$($default:expr)?; $($min:expr)?; $($max:expr)?]) => {
        $crate::dictionary::EntryInfo {
            sub: $sub,
            name: $name,
            data_type: $crate::dictionary::$type_of($get),
            bit_len: $crate::dictionary::$bits_of($get),
            access: $crate::__ecat_access!($($acc)|+),
            limits: $crate::dictionary::Limits(
                $crate::__ecat_limits!($($default)?; $($min)?; $($max)?).0
                    $(| { let _ = stringify!($unit); $crate::dictionary::Limits::UNIT })?
            ),
        }
    };
}

/// `Some(x)` or `None`.
#[doc(hidden)]
#[macro_export]
macro_rules! __ecat_some {
    () => {
        None
    };
    ($value:expr) => {
        Some($value)
    };
}

/// The `Limits` flags of the declared default, minimum and maximum.
#[doc(hidden)]
#[macro_export]
macro_rules! __ecat_limits {
    ($($default:expr)?; $($min:expr)?; $($max:expr)?) => {
        $crate::dictionary::Limits(
            0 $(| { let _ = stringify!($default); $crate::dictionary::Limits::DEFAULT })?
              $(| { let _ = stringify!($min); $crate::dictionary::Limits::MIN })?
              $(| { let _ = stringify!($max); $crate::dictionary::Limits::MAX })?
        )
    };
}
