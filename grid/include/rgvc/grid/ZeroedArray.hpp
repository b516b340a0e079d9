// ZeroedArray<T>: a fixed-size array of trivially copyable T that starts all zero bytes and costs memory
// only where it is written.
//
// Why not std::vector. A vector value-initializes every element on construction, which writes every page:
// a 512^3 grid's dense matrices (about 13 bytes a voxel, 1.7 GiB) took 7-10 s to construct and held all of
// that memory before the first object was added, for a world that is mostly empty (issue 10's "large,
// mostly empty world"). calloc of a large block instead maps fresh pages that the system guarantees to be
// zero and provides on first touch (glibc takes such blocks from mmap and skips clearing them), so a
// grid's construction is O(1) and its resident memory follows the parts of the world that are written
// (objects, TBVs, visited bricks). A library call does the work; this class only gives it ownership,
// bounds in Debug and the container calls the storage uses.
//
// Requirements: T trivially copyable, and an all-zero T is the value the storage means by "empty" (the
// dense storage encodes its cells so: VoxelStorage.hpp).
#pragma once

#include <cassert>
#include <cstddef>
#include <cstdlib>
#include <cstdint>
#include <cstring>
#include <new>
#include <type_traits>
#include <utility>

#ifdef __linux__
#include <sys/mman.h>
#endif

namespace rgvc {

template <class T> class ZeroedArray {
    static_assert(std::is_trivially_copyable_v<T>, "ZeroedArray holds raw bytes");

public:
    ZeroedArray() = default;
    /// n elements [Limit] n * sizeof(T) must fit in memory (throws std::bad_alloc otherwise), all bytes 0.
    explicit ZeroedArray(std::size_t n) { allocate(n); }
    ZeroedArray(const ZeroedArray& o) {
        allocate(o.m_size);
        if (o.m_huge) adviseHugePages();
        m_touched = o.m_touched;
        if (m_size != 0) std::memcpy(m_data, o.m_data, m_size * sizeof(T));
    }
    ZeroedArray(ZeroedArray&& o) noexcept
        : m_data(std::exchange(o.m_data, nullptr)), m_size(std::exchange(o.m_size, 0)), m_huge(std::exchange(o.m_huge, false)),
          m_touched(std::exchange(o.m_touched, false)) {}
    ZeroedArray& operator=(ZeroedArray o) noexcept {
        std::swap(m_data, o.m_data);
        std::swap(m_size, o.m_size);
        std::swap(m_huge, o.m_huge);
        std::swap(m_touched, o.m_touched);
        return *this;
    }
    ~ZeroedArray() { std::free(m_data); }

    std::size_t size() const { return m_size; }
    T* data() { return m_data; }
    const T* data() const { return m_data; }
    T& operator[](std::size_t i) {
        assert(i < m_size);
        return m_data[i];
    }
    const T& operator[](std::size_t i) const {
        assert(i < m_size);
        return m_data[i];
    }
    T* begin() { return m_data; }
    T* end() { return m_data + m_size; }
    const T* begin() const { return m_data; }
    const T* end() const { return m_data + m_size; }

    /// Asks the system for huge pages over the array (Linux, transparent_hugepage = madvise, Debian's
    /// default; elsewhere, or when refused, nothing changes). For arrays read all over, written or not: a
    /// read of a part never written maps the 2 MiB zero page instead of 512 small ones, while each first
    /// write then takes 2 MiB. The paper's per-voxel traversals read every voxel of the view: over an
    /// empty 512^3 grid with small pages they missed the TLB at every row (a row of cells is 4 KiB) and
    /// took 26 s a frame instead of 0.8 s. The brick walks read only the bricks that hold something, which
    /// are written, and keep small pages: memory that follows the content.
    void adviseHugePages() {
#ifdef __linux__
        constexpr std::size_t kHuge = std::size_t(2) << 20;
        const std::size_t bytes = m_size * sizeof(T);
        const auto lo = (reinterpret_cast<std::uintptr_t>(m_data) + kHuge - 1) & ~std::uintptr_t(kHuge - 1);
        const auto hi = (reinterpret_cast<std::uintptr_t>(m_data) + bytes) & ~std::uintptr_t(kHuge - 1);
        if (hi > lo) madvise(reinterpret_cast<void*>(lo), hi - lo, MADV_HUGEPAGE); // a hint: failure changes nothing
#endif
        m_huge = true;
    }

    /// Writes every page now (zeros, the same contents), so that no later first write faults: for arrays
    /// that a frame may reach anywhere, where a page's first touch in the middle of a frame (a camera
    /// flying into space it has not seen) cost more than the whole array's at construction.
    void touch() {
        if (m_size != 0) std::memset(static_cast<void*>(m_data), 0, m_size * sizeof(T));
        m_touched = true;
    }

    /// Every byte back to 0. An array written whole (touch) is filled in place; any other takes fresh zero
    /// pages (the old ones go back to the system): O(1) work, and the memory of what was written is given
    /// back, where a fill would write every page.
    void clear() {
        if (m_touched) {
            touch();
            return;
        }
        ZeroedArray fresh(m_size);
        if (m_huge) fresh.adviseHugePages();
        std::swap(m_data, fresh.m_data);
    }

private:
    void allocate(std::size_t n) {
        m_size = n;
        m_data = static_cast<T*>(std::calloc(n == 0 ? 1 : n, sizeof(T)));
        if (m_data == nullptr) throw std::bad_alloc();
    }

    T* m_data = nullptr;
    std::size_t m_size = 0;
    bool m_huge = false;    // adviseHugePages was called (a clear keeps it)
    bool m_touched = false; // touch was called (a clear keeps it)
};

} // namespace rgvc
