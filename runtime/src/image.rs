//! A device image seen through its layout. Every read and write of the
//! runtime goes through an `Image`, whether the image has the full layout
//! (`Memory`) or a compact one (only the devices one program uses), so both
//! are served by the same code and every engine's tests test it.
//!
//! A device that the layout does not hold reads 0 and is not written: the
//! program never names one (its layout was made from it), the runtime's own
//! writes to special devices nobody reads are dropped, and a host that asks
//! for one is told (`holds`). A write through an instruction's operand
//! (`Place::write`) to a device the layout lacks counts in
//! `Scalar::LayoutMisses` (tests insist on 0).
//!
//! Reads and writes go through byte slices with bounds checks, so no
//! layout, however damaged, takes them outside the image.

use crate::device::{BitArea, WordArea, FIRST_WIDE_COUNTER};
use crate::layout::{
    Array, ImageHeader, Layout, Run, Scalar, COMPACT_MAGIC, FULL, FULL_MAGIC, HEADER_SIZE, MEMORY_ALIGN, MEMORY_SIZE,
};
use crate::memory::{join_words, split_words, InstanceState, Memory};
use crate::special::{OperationError, D_ERROR_CODE, D_ERROR_LINE, M_OPERATION_ERROR};

/// Which layout an image has.
#[derive(Clone, Copy, Debug)]
enum Which<'a> {
    /// `layout::FULL`, known at compile time (so its offsets fold).
    Full,
    Compact(&'a Layout),
}

/// An image: its bytes (`&[u8]` to read, `&mut [u8]` to write too) and its
/// layout.
#[derive(Debug)]
pub struct Image<'a, B> {
    bytes: B,
    layout: Which<'a>,
}

/// An image that can be written.
pub type ImageMut<'a> = Image<'a, &'a mut [u8]>;
/// An image that can only be read.
pub type ImageRef<'a> = Image<'a, &'a [u8]>;

/// Anything that shows an image to read: `Memory`, an `Image`.
pub trait AsImage {
    fn as_image(&self) -> ImageRef<'_>;
}

/// Anything that shows an image to write.
pub trait AsImageMut: AsImage {
    fn as_image_mut(&mut self) -> ImageMut<'_>;
}

impl AsImage for Memory {
    fn as_image(&self) -> ImageRef<'_> {
        Image {
            bytes: bytemuck::bytes_of(self),
            layout: Which::Full,
        }
    }
}

impl AsImageMut for Memory {
    fn as_image_mut(&mut self) -> ImageMut<'_> {
        Image {
            bytes: bytemuck::bytes_of_mut(self),
            layout: Which::Full,
        }
    }
}

#[cfg(any(feature = "std", test))]
impl<T: AsImage + ?Sized> AsImage for Box<T> {
    fn as_image(&self) -> ImageRef<'_> {
        (**self).as_image()
    }
}

#[cfg(any(feature = "std", test))]
impl<T: AsImageMut + ?Sized> AsImageMut for Box<T> {
    fn as_image_mut(&mut self) -> ImageMut<'_> {
        (**self).as_image_mut()
    }
}

impl<B: AsRef<[u8]>> AsImage for Image<'_, B> {
    fn as_image(&self) -> ImageRef<'_> {
        Image {
            bytes: self.bytes.as_ref(),
            layout: self.layout,
        }
    }
}

impl AsImageMut for ImageMut<'_> {
    fn as_image_mut(&mut self) -> ImageMut<'_> {
        Image {
            bytes: &mut *self.bytes,
            layout: self.layout,
        }
    }
}

/// Why `ImageMut::init` refused storage.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum InitError {
    /// Smaller than the layout's size.
    TooSmall,
    /// Not aligned to `MEMORY_ALIGN`.
    Misaligned,
    /// A layout table of another version, or one that does not fit itself.
    BadLayout,
}

impl<'a> ImageMut<'a> {
    /// Initialises `storage` as an image with `layout` (`None`: the full
    /// layout): everything 0, the header written. The table must stay where
    /// it is while the image is used (it is named by address).
    pub fn init(storage: &'a mut [u8], layout: Option<&'a Layout>) -> Result<ImageMut<'a>, InitError> {
        let size = match layout {
            None => MEMORY_SIZE,
            Some(layout) if layout.is_valid() => layout.size as usize,
            Some(_) => return Err(InitError::BadLayout),
        };
        if !(storage.as_ptr() as usize).is_multiple_of(MEMORY_ALIGN) {
            return Err(InitError::Misaligned);
        }
        let storage = storage.get_mut(..size).ok_or(InitError::TooSmall)?;
        storage.fill(0);
        let address = layout.map_or(0, |l| l as *const Layout as usize as u64);
        let header = ImageHeader {
            magic: if layout.is_some() { COMPACT_MAGIC } else { FULL_MAGIC },
            size: size as u32,
            layout_low: address as u32,
            layout_high: (address >> 32) as u32,
        };
        storage[..HEADER_SIZE].copy_from_slice(bytemuck::bytes_of(&header));
        Ok(Image {
            bytes: storage,
            layout: layout.map_or(Which::Full, Which::Compact),
        })
    }

    /// The image at `image`, as its header describes it; `None` for a
    /// null pointer or storage that was never initialised.
    ///
    /// # Safety
    /// `image` is null or was initialised by `init` (or the C API's
    /// `ladder_init`/`ladder_init_layout`), is valid for its size, and no
    /// other reference to it is used while the result lives; a compact
    /// image's layout table is still where it was.
    #[inline(always)]
    pub unsafe fn from_raw(image: *mut u8) -> Option<ImageMut<'a>> {
        // SAFETY: the caller's contract.
        let (size, layout) = unsafe { describe(image)? };
        // SAFETY: `size` bytes from `image` are the image (the contract).
        let bytes = unsafe { core::slice::from_raw_parts_mut(image, size) };
        Some(Image { bytes, layout })
    }

    /// The same image, borrowed again (for calls that take it by value).
    pub fn reborrow(&mut self) -> ImageMut<'_> {
        self.as_image_mut()
    }
}

impl<'a> ImageRef<'a> {
    /// As `ImageMut::from_raw`, to read.
    ///
    /// # Safety
    /// As `ImageMut::from_raw`, except that other readers may exist.
    pub unsafe fn from_raw(image: *const u8) -> Option<ImageRef<'a>> {
        // SAFETY: the caller's contract.
        let (size, layout) = unsafe { describe(image)? };
        // SAFETY: `size` bytes from `image` are the image (the contract).
        let bytes = unsafe { core::slice::from_raw_parts(image, size) };
        Some(Image { bytes, layout })
    }
}

/// The size and layout an image's header names.
///
/// # Safety
/// `image` is null or points at an initialised image (at least a header).
#[inline(always)]
unsafe fn describe<'a>(image: *const u8) -> Option<(usize, Which<'a>)> {
    if image.is_null() {
        return None;
    }
    // SAFETY: an initialised image starts with its header.
    let header = unsafe { image.cast::<ImageHeader>().read_unaligned() };
    match header.magic {
        FULL_MAGIC if header.size as usize == MEMORY_SIZE => Some((MEMORY_SIZE, Which::Full)),
        COMPACT_MAGIC => {
            let address = (u64::from(header.layout_high) << 32) | u64::from(header.layout_low);
            let table = usize::try_from(address).ok()? as *const Layout;
            if table.is_null() || !(table as usize).is_multiple_of(align_of::<Layout>()) {
                return None;
            }
            // SAFETY: `init` wrote the address of a valid table, which the
            // caller keeps in place.
            let layout = unsafe { &*table };
            (layout.size == header.size && layout.size as usize >= HEADER_SIZE)
                .then_some((layout.size as usize, Which::Compact(layout)))
        }
        _ => None,
    }
}

impl<B: AsRef<[u8]>> Image<'_, B> {
    /// The layout table.
    pub fn layout(&self) -> &Layout {
        match self.layout {
            Which::Full => &FULL,
            Which::Compact(layout) => layout,
        }
    }

    /// Is this the full layout?
    pub fn is_full(&self) -> bool {
        matches!(self.layout, Which::Full)
    }

    /// Has the image the layout table at `table` (null: the full layout)?
    #[inline(always)]
    pub fn has_layout(&self, table: *const Layout) -> bool {
        match self.layout {
            Which::Full => table.is_null(),
            Which::Compact(layout) => core::ptr::eq(layout, table),
        }
    }

    /// The image's bytes.
    pub fn bytes(&self) -> &[u8] {
        self.bytes.as_ref()
    }

    #[inline(always)]
    fn run(&self, segment: usize) -> Run {
        match self.layout {
            Which::Full => FULL.runs[segment],
            Which::Compact(layout) => layout.runs[segment],
        }
    }

    /// Byte offset of element `n` of `array`; `None` when the image does
    /// not hold it.
    #[inline]
    pub fn offset(&self, array: Array, n: u32) -> Option<usize> {
        let run = self.run(array.segment(n)?);
        let k = n.wrapping_sub(run.first);
        (k < run.count).then(|| run.offset as usize + k as usize * array.size())
    }

    /// Does the image hold element `n` of `array`?
    pub fn holds(&self, array: Array, n: u32) -> bool {
        self.offset(array, n).is_some()
    }

    #[inline]
    fn load<const N: usize>(&self, array: Array, n: u32) -> Option<[u8; N]> {
        let at = self.offset(array, n)?;
        self.bytes.as_ref().get(at..at + N)?.try_into().ok()
    }

    /// Element `n` of a byte array; 0 when not held.
    #[inline]
    pub fn get_u8(&self, array: Array, n: u32) -> u8 {
        self.load::<1>(array, n).map_or(0, |[b]| b)
    }

    /// Element `n` of a 16-bit array; 0 when not held.
    #[inline]
    pub fn get_i16(&self, array: Array, n: u32) -> i16 {
        self.load(array, n).map_or(0, i16::from_ne_bytes)
    }

    /// Element `n` of a 32-bit array; 0 when not held.
    #[inline]
    pub fn get_i32(&self, array: Array, n: u32) -> i32 {
        self.load(array, n).map_or(0, i32::from_ne_bytes)
    }

    /// Element `n` of a 32-bit array, unsigned; 0 when not held.
    #[inline]
    pub fn get_u32(&self, array: Array, n: u32) -> u32 {
        self.get_i32(array, n) as u32
    }

    /// Instance state `n`; `None` when not held (the program has fewer).
    pub fn instance(&self, n: u32) -> Option<InstanceState> {
        self.load::<{ size_of::<InstanceState>() }>(Array::Instance, n)
            .map(|bytes| bytemuck::pod_read_unaligned(&bytes))
    }

    /// A scalar of the scan.
    #[inline(always)]
    pub fn scalar(&self, scalar: Scalar) -> u32 {
        let at = scalar.offset();
        self.bytes
            .as_ref()
            .get(at..at + 4)
            .and_then(|b| b.try_into().ok())
            .map_or(0, u32::from_ne_bytes)
    }

    // ---- devices, as programs and hosts name them ----

    /// Reads bit `index` of `area`; `None` when it is outside the area.
    pub fn bit(&self, area: BitArea, index: u32) -> Option<bool> {
        (index < area.count()).then(|| self.get_u8(Array::of_bits(area), index) != 0)
    }

    /// Reads word `index` of `area`; `None` when it is outside the area.
    pub fn word(&self, area: WordArea, index: u32) -> Option<i16> {
        (index < area.count()).then(|| self.get_i16(Array::of_words(area), index))
    }

    /// 32-bit value of the pair (index+1, index): low word at `index`. A
    /// pair never crosses the end of its run (a buffer memory's unit).
    pub fn word_pair(&self, area: WordArea, index: u32) -> Option<i32> {
        let high_index = pair_high(area, index)?;
        Some(join_words(self.word(area, index)?, self.word(area, high_index)?))
    }

    /// Current value of counter C200–C255 (`counter` is the device number).
    pub fn wide_counter(&self, counter: u32) -> Option<i32> {
        (FIRST_WIDE_COUNTER..Array::WideCounterValue.end())
            .contains(&counter)
            .then(|| self.get_i32(Array::WideCounterValue, counter))
    }

    /// Value of the 4·`digits` consecutive bits starting at `start`
    /// (`KnM0`): first device is bit 0.
    pub fn digits(&self, area: BitArea, start: u32, digits: u32) -> Option<i32> {
        let count = 4 * digits;
        if u64::from(start) + u64::from(count) > u64::from(area.count()) {
            return None;
        }
        let array = Array::of_bits(area);
        Some((0..count).fold(0u32, |acc, i| {
            acc | (u32::from(self.get_u8(array, start + i) != 0) << i)
        }) as i32)
    }

    /// The latest operation error code, when M8067 is ON.
    pub fn operation_error(&self) -> Option<u16> {
        (self.get_u8(Array::M, M_OPERATION_ERROR) != 0).then(|| self.get_i16(Array::D, D_ERROR_CODE) as u16)
    }

    /// `digest` of the image's bytes.
    pub fn digest(&self) -> u64 {
        digest(self.bytes.as_ref())
    }
}

/// FNV-1a over an image's 64-bit little-endian words after its header (the
/// last one padded with zeros): how test drivers and hosts compare images
/// (all but their header) cheaply, whatever their layout. Each step is a
/// bijection of the hash for a given word, so two images that differ in
/// one word always hash differently. The header is left out: a compact image's names its layout
/// table by address. Here, in the optimised runtime, because test builds
/// hash every image of every scan of every engine.
pub fn digest(bytes: &[u8]) -> u64 {
    let words = bytes.get(HEADER_SIZE..).unwrap_or(&[]).chunks(8);
    words.fold(0xcbf2_9ce4_8422_2325u64, |hash, chunk| {
        let mut word = [0u8; 8];
        word[..chunk.len()].copy_from_slice(chunk);
        (hash ^ u64::from_le_bytes(word)).wrapping_mul(0x0000_0100_0000_01b3)
    })
}

/// The high word of the pair at `index`, inside the same run of the area.
fn pair_high(area: WordArea, index: u32) -> Option<u32> {
    let high_index = index.checked_add(1)?;
    (index < area.count() && high_index < area.reach(index).1).then_some(high_index)
}

impl ImageMut<'_> {
    #[inline]
    fn store<const N: usize>(&mut self, array: Array, n: u32, value: [u8; N]) -> bool {
        let Some(at) = self.offset(array, n) else {
            return false;
        };
        // Through a fixed-size array: a plain store, not a call to a
        // slice copy (which an image built for size keeps out of line).
        match self
            .bytes
            .get_mut(at..at + N)
            .and_then(|cell| <&mut [u8; N]>::try_from(cell).ok())
        {
            Some(cell) => {
                *cell = value;
                true
            }
            None => false,
        }
    }

    /// Writes element `n` of a byte array; false when not held.
    #[inline]
    pub fn set_u8(&mut self, array: Array, n: u32, value: u8) -> bool {
        self.store(array, n, [value])
    }

    /// Writes element `n` of a 16-bit array; false when not held.
    #[inline]
    pub fn set_i16(&mut self, array: Array, n: u32, value: i16) -> bool {
        self.store(array, n, value.to_ne_bytes())
    }

    /// Writes element `n` of a 32-bit array; false when not held.
    #[inline]
    pub fn set_i32(&mut self, array: Array, n: u32, value: i32) -> bool {
        self.store(array, n, value.to_ne_bytes())
    }

    /// Writes element `n` of a 32-bit array, unsigned; false when not held.
    #[inline]
    pub fn set_u32(&mut self, array: Array, n: u32, value: u32) -> bool {
        self.store(array, n, value.to_ne_bytes())
    }

    /// Writes instance state `n`; false when not held.
    pub fn set_instance(&mut self, n: u32, state: InstanceState) -> bool {
        let mut bytes = [0u8; size_of::<InstanceState>()];
        bytes.copy_from_slice(bytemuck::bytes_of(&state));
        self.store(Array::Instance, n, bytes)
    }

    /// Writes a scalar of the scan.
    #[inline(always)]
    pub fn set_scalar(&mut self, scalar: Scalar, value: u32) {
        let at = scalar.offset();
        if let Some(cell) = self
            .bytes
            .get_mut(at..at + 4)
            .and_then(|cell| <&mut [u8; 4]>::try_from(cell).ok())
        {
            *cell = value.to_ne_bytes();
        }
    }

    /// A write by the program to a device the image lacks (see the module).
    pub(crate) fn missed(&mut self) {
        let misses = self.scalar(Scalar::LayoutMisses);
        self.set_scalar(Scalar::LayoutMisses, misses.saturating_add(1));
    }

    /// Writes bit `index` of `area`; false when it is outside the area.
    pub fn set_bit(&mut self, area: BitArea, index: u32, on: bool) -> bool {
        index < area.count() && {
            self.set_u8(Array::of_bits(area), index, on as u8);
            true
        }
    }

    /// Writes word `index` of `area`; false when it is outside the area.
    pub fn set_word(&mut self, area: WordArea, index: u32, value: i16) -> bool {
        index < area.count() && {
            self.set_i16(Array::of_words(area), index, value);
            true
        }
    }

    /// Writes the pair (index+1, index); false when it is outside the run.
    pub fn set_word_pair(&mut self, area: WordArea, index: u32, value: i32) -> bool {
        let Some(high_index) = pair_high(area, index) else {
            return false;
        };
        let (low, high) = split_words(value);
        self.set_word(area, index, low) && self.set_word(area, high_index, high)
    }

    /// Writes the current value of counter C200–C255.
    pub fn set_wide_counter(&mut self, counter: u32, value: i32) -> bool {
        (FIRST_WIDE_COUNTER..Array::WideCounterValue.end()).contains(&counter) && {
            self.set_i32(Array::WideCounterValue, counter, value);
            true
        }
    }

    /// Writes the low 4·`digits` bits of `value` to the bits from `start`.
    pub fn set_digits(&mut self, area: BitArea, start: u32, digits: u32, value: i32) -> bool {
        let count = 4 * digits;
        if u64::from(start) + u64::from(count) > u64::from(area.count()) {
            return false;
        }
        let array = Array::of_bits(area);
        for i in 0..count {
            self.set_u8(array, start + i, ((value as u32 >> i) & 1) as u8);
        }
        true
    }

    /// Records an operation error: M8067 ON, D8067 = code, D8069 = line.
    /// Errors stay until the program or the host clears them.
    pub fn record_error(&mut self, error: OperationError, line: u32) {
        self.set_u8(Array::M, M_OPERATION_ERROR, 1);
        self.set_i16(Array::D, D_ERROR_CODE, error.code() as i16);
        // D8069 is one word: lines past 32767 keep their low 16 bits.
        self.set_i16(Array::D, D_ERROR_LINE, line as u16 as i16);
    }

    /// Copies every element of byte array `from` that the image holds onto
    /// the same element of byte array `to` (arrays numbered alike, such as
    /// the input image and X), where `to` holds it too.
    #[inline(always)]
    pub(crate) fn copy_bytes(&mut self, from: Array, to: Array) {
        let (mut sa, mut sb) = (from.segments(), to.segments());
        // Parallel arrays have the same segments; these have one each.
        if sa.len() == 1 && sb.len() == 1 {
            return self.copy_run(from, sa.start, to, sb.start);
        }
        while let (Some(a), Some(b)) = (sa.next(), sb.next()) {
            self.copy_run(from, a, to, b);
        }
    }

    /// `copy_bytes` for segment `a` of `from` and `b` of `to`: one move
    /// when both hold the same devices (every layout lays parallel arrays
    /// out alike).
    #[inline(always)]
    fn copy_run(&mut self, from: Array, a: usize, to: Array, b: usize) {
        let (ra, rb) = (self.run(a), self.run(b));
        if ra.first == rb.first && ra.count == rb.count {
            let (ao, bo, count) = (ra.offset as usize, rb.offset as usize, ra.count as usize);
            let fits = |o: usize| o.checked_add(count).is_some_and(|end| end <= self.bytes.len());
            if fits(ao) && fits(bo) {
                let base = self.bytes.as_mut_ptr();
                // SAFETY: both ranges lie inside the image's bytes (checked
                // just above); `copy` allows them to overlap. (`copy_within`
                // does the same, but a runtime built for size calls it out of
                // line at every scan.)
                unsafe { core::ptr::copy(base.add(ao), base.add(bo), count) };
            }
            return;
        }
        for n in rb.first..rb.first.saturating_add(rb.count) {
            if self.holds(from, n) {
                let value = self.get_u8(from, n);
                self.set_u8(to, n, value);
            }
        }
    }

    /// Calls `each` with element n of byte array `a` and element n of byte
    /// array `b` (arrays numbered alike, such as a force table and its
    /// devices) for every n the image holds in both, and keeps what it
    /// leaves in them. Parallel arrays have the same runs in every layout,
    /// so this walks two byte ranges.
    pub(crate) fn zip_bytes(&mut self, a: Array, b: Array, mut each: impl FnMut(&mut u8, &mut u8)) {
        for (sa, sb) in a.segments().zip(b.segments()) {
            let (ra, rb) = (self.run(sa), self.run(sb));
            if ra.first == rb.first && ra.count == rb.count {
                let (ao, bo, count) = (ra.offset as usize, rb.offset as usize, ra.count as usize);
                let fits = |o: usize| o.checked_add(count).is_some_and(|end| end <= self.bytes.len());
                if !(fits(ao) && fits(bo)) {
                    continue;
                }
                for k in 0..count {
                    let (mut va, mut vb) = (self.bytes[ao + k], self.bytes[bo + k]);
                    each(&mut va, &mut vb);
                    self.bytes[ao + k] = va;
                    self.bytes[bo + k] = vb;
                }
            } else {
                for n in rb.first..rb.first.saturating_add(rb.count) {
                    if self.holds(a, n) {
                        let (mut va, mut vb) = (self.get_u8(a, n), self.get_u8(b, n));
                        each(&mut va, &mut vb);
                        self.set_u8(a, n, va);
                        self.set_u8(b, n, vb);
                    }
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::layout::LayoutBuilder;

    #[test]
    fn a_compact_image_reads_what_it_holds_and_zero_elsewhere() {
        let layout = LayoutBuilder::new()
            .include_bits(BitArea::Y, 0, 8)
            .include_words(WordArea::D, 100, 102)
            .include_bits(BitArea::M, 8067, 8068)
            .include_words(WordArea::D, 8067, 8070)
            .build();
        let mut storage = vec![0u32; layout.size as usize / 4];
        let bytes: &mut [u8] = bytemuck::cast_slice_mut(&mut storage);
        let mut image = ImageMut::init(bytes, Some(&layout)).unwrap();
        assert!(image.set_word_pair(WordArea::D, 100, 0x0001_0002));
        assert_eq!(image.word_pair(WordArea::D, 100), Some(0x0001_0002));
        assert!(image.set_word(WordArea::D, 5, 7), "inside the area: no error");
        assert_eq!(image.word(WordArea::D, 5), Some(0), "not held: reads 0");
        assert_eq!(image.word(WordArea::D, 8512), None);
        image.record_error(OperationError::ReadOutOfRange, 40);
        assert_eq!(image.operation_error(), Some(0x4085));
        assert!(image.set_bit(BitArea::Y, 7, true));
        assert_eq!(image.digits(BitArea::Y, 4, 1), Some(8));
        // The header names the layout: the raw pointer finds it again.
        let pointer = image.bytes.as_mut_ptr();
        let again = unsafe { ImageMut::from_raw(pointer) }.unwrap();
        assert_eq!(again.word_pair(WordArea::D, 100), Some(0x0001_0002));
        assert!(!again.is_full());
    }

    #[test]
    fn storage_that_was_never_initialised_is_refused() {
        let mut storage = vec![0u32; 64];
        assert!(unsafe { ImageMut::from_raw(storage.as_mut_ptr().cast()) }.is_none());
        assert!(unsafe { ImageMut::from_raw(core::ptr::null_mut()) }.is_none());
        let layout = LayoutBuilder::new().include_bits(BitArea::X, 0, 8).build();
        let bytes: &mut [u8] = bytemuck::cast_slice_mut(&mut storage);
        assert_eq!(
            ImageMut::init(&mut bytes[..8], Some(&layout)).err(),
            Some(InitError::TooSmall)
        );
        assert_eq!(
            ImageMut::init(&mut bytes[1..], Some(&layout)).err(),
            Some(InitError::Misaligned)
        );
        let mut damaged = layout;
        damaged.version = 0;
        assert_eq!(ImageMut::init(bytes, Some(&damaged)).err(), Some(InitError::BadLayout));
    }
}
