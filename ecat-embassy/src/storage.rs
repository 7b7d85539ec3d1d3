//! Stored parameters in flash: what performs the "save" and "load" commands of 0x1010/0x1011
//! ([`ecat_core::dictionary::parameters`]) and loads the stored set at start-up.
//!
//! A firmware with storage hands the state-machine runner a [`Storage`]
//! ([`StateMachineRunner::with_storage`](crate::StateMachineRunner::with_storage)); the default,
//! `()`, is none: no code, and a dictionary without `stored = …` has no 0x1010/0x1011.
//!
//! **When the answer goes out.** The runner asks its storage after every mailbox message it
//! served, before the answer is written to SM1 ([`Storage::take`], then [`Storage::commit`]): a
//! "save" is answered once the record is in flash, as SSC answers after storing. The values
//! stored are those of that moment; the process-data runner goes on meanwhile. A flash failure
//! cannot turn the already built answer into an abort: it raises the emergency
//! [`STORE_FAILED`] instead (a wrong signature is refused with 0x08000020 by the SDO write
//! itself).
//!
//! `FlashStorage` (feature `storage`) keeps the record in a NOR flash partition with
//! `sequential-storage`'s `map`: one key, whose newest complete item is
//! the parameter set. An item is written after the old one and found by its CRC, so a power
//! cut at any flash operation of a save leaves the old set or the new one, never a mix; the
//! crate erases a page only when the other holds the newest item.

use ecat_core::coe::Emergency;

/// The emergency a failed store raises: 0x5000 "device hardware" (CiA 301 Table 21), error
/// register bit 0 (generic error).
pub const STORE_FAILED: Emergency = Emergency {
    code: 0x5000,
    register: 0x01,
    data: [0x10, 0x10, 0, 0, 0],
};

/// What performs the stored-parameter commands for the state-machine runner.
pub trait Storage<D> {
    /// Whether this is a storage at all: `false` for `()`, whose runner then carries no code
    /// for it (not even the lock of the dictionary after each message).
    const STORES: bool = true;

    /// Takes the command a served message left in `od` (with the dictionary locked) and
    /// prepares its flash write: whether [`Storage::commit`] is due.
    fn take(&mut self, od: &mut D) -> bool;

    /// Performs the prepared write; the emergency to raise when it failed.
    fn commit(&mut self) -> impl Future<Output = Option<Emergency>>;
}

/// No storage.
impl<D> Storage<D> for () {
    const STORES: bool = false;

    fn take(&mut self, _: &mut D) -> bool {
        false
    }

    fn commit(&mut self) -> impl Future<Output = Option<Emergency>> {
        // Not an `async fn`: its future would carry a "resumed after completion" panic into
        // every runner's state machine, where the await stays though `STORES` skips it.
        core::future::poll_fn(|_| core::task::Poll::Ready(None))
    }
}

/// A storage or none, chosen at start-up.
impl<D, S: Storage<D>> Storage<D> for Option<S> {
    fn take(&mut self, od: &mut D) -> bool {
        self.as_mut().is_some_and(|s| s.take(od))
    }

    async fn commit(&mut self) -> Option<Emergency> {
        self.as_mut()?.commit().await
    }
}

#[cfg(feature = "storage")]
pub use flash::{FlashStorage, LoadError};

#[cfg(feature = "storage")]
mod flash {
    use ecat_core::coe::Emergency;
    use ecat_core::dictionary::ObjectDictionary;
    use ecat_core::dictionary::parameters::{self, Command, Loaded};
    use embedded_storage_async::nor_flash::NorFlash;
    use sequential_storage::cache::{Cache, Uncached};
    use sequential_storage::map::{MapConfig, MapStorage};

    use super::{STORE_FAILED, Storage};

    /// The one key of the map: the parameter set.
    const KEY: u8 = 0;

    /// What the map's buffer holds beyond the record: the key (1 byte) and the rounding of the
    /// item to the flash's write size (at most sequential-storage's largest word, 32 bytes).
    const MAP_OVERHEAD: usize = 33;

    /// Why [`FlashStorage::new`] or [`FlashStorage::load`] failed.
    #[derive(Debug, Clone, Copy, PartialEq, Eq)]
    #[cfg_attr(feature = "defmt", derive(defmt::Format))]
    pub enum LoadError {
        /// The partition is not two or more whole erase pages.
        Partition,
        /// The flash could not be read, or holds no valid map (the defaults stay).
        Flash,
    }

    /// The parameter set in a NOR flash partition `F` (at least two erase pages, e.g. the
    /// PARAMETERS pages of the STM32 firmware), with room for a record of `N` bytes less
    /// `MAP_OVERHEAD` (33: the map's key and word rounding): [`parameters::record_size`] tells
    /// what the dictionary needs.
    pub struct FlashStorage<F: NorFlash, const N: usize> {
        map: MapStorage<u8, F, Cache<Uncached, Uncached, Uncached, u8>>,
        /// The record to store.
        record: [u8; N],
        /// The prepared write: the record's length, or `Err` when it did not fit.
        pending: Option<Result<usize, ()>>,
        /// The map's buffer.
        buffer: [u8; N],
    }

    impl<F: NorFlash, const N: usize> FlashStorage<F, N> {
        /// The storage over the whole of `flash`.
        pub fn new(flash: F) -> Result<Self, LoadError> {
            let end = u32::try_from(flash.capacity()).map_err(|_| LoadError::Partition)?;
            let config = MapConfig::try_new(0..end).map_err(|_| LoadError::Partition)?;
            Ok(Self {
                map: MapStorage::new(flash, config, Cache::new_uncached()),
                record: [0; N],
                pending: None,
                buffer: [0; N],
            })
        }

        /// Loads the stored set into `od` (at start-up, before the runners): what was applied
        /// and skipped, also kept in `od`'s [`StoredParameters`](parameters::StoredParameters).
        /// Without a stored set, or after "load", `od` keeps its defaults.
        pub async fn load<D: ObjectDictionary>(&mut self, od: &mut D) -> Result<Loaded, LoadError> {
            let record: Option<&[u8]> = self
                .map
                .fetch_item(&mut self.buffer, &KEY)
                .await
                .map_err(|_| LoadError::Flash)?;
            let loaded = record.map_or(Loaded::default(), |r| parameters::load(od, r));
            if let Some(state) = od.stored_parameters() {
                state.loaded = loaded;
            }
            Ok(loaded)
        }

        /// The room a record has.
        fn room(&mut self) -> &mut [u8] {
            let room = N.saturating_sub(MAP_OVERHEAD);
            self.record.get_mut(..room).unwrap_or_default()
        }
    }

    impl<D: ObjectDictionary, F: NorFlash, const N: usize> Storage<D> for FlashStorage<F, N> {
        fn take(&mut self, od: &mut D) -> bool {
            let Some(command) = od.stored_parameters().and_then(|s| s.take()) else {
                return false;
            };
            self.pending = Some(match command {
                Command::Save => parameters::save(od, self.room()).map_err(|_| ()),
                // The defaults at the next reset: an empty set.
                Command::RestoreDefaults => Ok(0),
            });
            true
        }

        async fn commit(&mut self) -> Option<Emergency> {
            let len = match self.pending.take()? {
                Ok(len) => len,
                Err(()) => return Some(STORE_FAILED),
            };
            let record = self.record.get(..len).unwrap_or_default();
            let stored = self.map.store_item(&mut self.buffer, &KEY, &record).await;
            stored.err().map(|_| STORE_FAILED)
        }
    }
}
