// A flat hash set of packed octree keys for the insertion hot path: open
// addressing with linear probing, cleared per scan in O(inserted), never
// shrinking, so a steady stream of scans allocates nothing.
#pragma once

#include "OcTreeKeys.h"

#include <algorithm>
#include <cstdint>
#include <vector>

namespace avm::detail
{
class KeySet
{
   public:
	KeySet() { m_slots.assign(1u << 12, 0); }

	void clear()
	{
		for (const auto k : m_keys) m_slots[slotOf(k)] = 0;
		m_keys.clear();
	}
	/** True if the key was not there yet. */
	bool insert(std::uint64_t key)
	{
		if (2 * (m_keys.size() + 1) > m_slots.size()) grow();
		std::size_t i = hash(key);
		while (m_slots[i] != 0)
		{
			if (m_slots[i] == key) return false;
			i = (i + 1) & mask();
		}
		m_slots[i] = key;
		m_keys.push_back(key);
		return true;
	}
	bool contains(std::uint64_t key) const
	{
		std::size_t i = hash(key);
		while (m_slots[i] != 0)
		{
			if (m_slots[i] == key) return true;
			i = (i + 1) & mask();
		}
		return false;
	}
	/** The keys in insertion order. */
	const std::vector<std::uint64_t>& keys() const { return m_keys; }

   private:
	std::size_t mask() const { return m_slots.size() - 1; }
	std::size_t hash(std::uint64_t key) const
	{
		// Fibonacci hashing spreads the neighbouring keys of a scan.
		return static_cast<std::size_t>((key * 0x9E3779B97F4A7C15ull) >> 20) & mask();
	}
	std::size_t slotOf(std::uint64_t key) const
	{
		std::size_t i = hash(key);
		while (m_slots[i] != key) i = (i + 1) & mask();
		return i;
	}
	void grow()
	{
		m_slots.assign(m_slots.size() * 2, 0);
		for (const auto k : m_keys)
		{
			std::size_t i = hash(k);
			while (m_slots[i] != 0) i = (i + 1) & mask();
			m_slots[i] = k;
		}
	}

	std::vector<std::uint64_t> m_slots;
	std::vector<std::uint64_t> m_keys;
};
}  // namespace avm::detail

namespace avm::detail
{
/** A KeySet for keys inside a known box of voxels: a dense array of scan
 *  stamps instead of hashing (the fine tree's keys all lie in the regions).
 *  Keys outside the box are not stored (insert() returns false); a box too
 *  large for the array falls back to hashing. */
class BoxKeySet
{
   public:
	/** Starts a scan over keys in [lo, hi] (inclusive, per axis). */
	void reset(const octomap::OcTreeKey& lo, const octomap::OcTreeKey& hi)
	{
		m_sparse.clear();
		m_keys.clear();
		for (int i = 0; i < 3; i++)
		{
			m_lo[i] = lo[i];
			m_dim[i] = static_cast<std::size_t>(hi[i]) - lo[i] + 1;
		}
		const std::size_t cells = m_dim[0] * m_dim[1] * m_dim[2];
		m_dense = cells <= kMaxCells;
		if (!m_dense) return;
		if (m_stamp.size() < cells) m_stamp.assign(cells, 0);
		if (++m_current == 0)  // wrapped: forget all stamps
		{
			std::fill(m_stamp.begin(), m_stamp.end(), 0);
			m_current = 1;
		}
	}
	bool insert(std::uint64_t key)
	{
		if (!m_dense) return m_sparse.insert(key);
		const auto i = indexOf(key);
		if (i == kOutside || m_stamp[i] == m_current) return false;
		m_stamp[i] = m_current;
		m_keys.push_back(key);
		return true;
	}
	bool contains(std::uint64_t key) const
	{
		if (!m_dense) return m_sparse.contains(key);
		const auto i = indexOf(key);
		return i != kOutside && m_stamp[i] == m_current;
	}
	const std::vector<std::uint64_t>& keys() const { return m_dense ? m_keys : m_sparse.keys(); }

   private:
	static constexpr std::size_t kMaxCells = std::size_t(1) << 24;
	static constexpr std::size_t kOutside = ~std::size_t(0);
	std::size_t indexOf(std::uint64_t packed) const
	{
		const auto k = unpackKey(packed);
		const std::size_t x = std::size_t(k[0]) - m_lo[0], y = std::size_t(k[1]) - m_lo[1], z = std::size_t(k[2]) - m_lo[2];
		// Below the box the subtraction wraps to a huge value.
		if (x >= m_dim[0] || y >= m_dim[1] || z >= m_dim[2]) return kOutside;
		return (x * m_dim[1] + y) * m_dim[2] + z;
	}

	bool m_dense = false;
	std::size_t m_lo[3] = {0, 0, 0}, m_dim[3] = {0, 0, 0};
	std::vector<std::uint32_t> m_stamp;
	std::uint32_t m_current = 0;
	std::vector<std::uint64_t> m_keys;
	KeySet m_sparse;
};
}  // namespace avm::detail
