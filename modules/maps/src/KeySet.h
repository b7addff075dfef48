// A flat hash set of packed octree keys for the insertion hot path: open
// addressing with linear probing, cleared per scan in O(inserted) (or one pass
// over the table when the keys fill a good part of it), never shrinking, so a
// steady stream of scans allocates nothing.
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
		// Finding each key's slot again is a cache miss per key once the
		// table outgrows the cache: past a few keys a slot, zeroing the whole
		// table in order is cheaper.
		if (m_keys.size() * 16 > m_slots.size())
			std::fill(m_slots.begin(), m_slots.end(), 0);
		else
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
/** A KeySet for keys inside a known box of voxels: one bit per voxel instead
 *  of hashing (the high tree's keys all lie in the regions, a ray's keys outside
 *  them within the tree's max range of its origin). The bits of
 *  4 x 4 x 4 voxels share a word, so a ray's next voxel is mostly in a word
 *  just read, and a box of regions takes a few tens of kB, not the MB a word
 *  per voxel took (the high tree's ray lookups were cache misses). Keys outside
 *  the box are not stored (insert() returns false); a box too large for the
 *  bits falls back to hashing. */
class BoxKeySet
{
   public:
	/** Starts a scan over keys in [lo, hi] (inclusive, per axis). */
	void reset(const octomap::OcTreeKey& lo, const octomap::OcTreeKey& hi)
	{
		// A scan's keys touch few words of a large box (a surface's voxels
		// in a box of the sensor's range): zeroing those words instead of
		// all of them spares writing megabytes, which pushes other data out
		// of the cache.
		const bool zeroed = m_dense && m_keys.size() * 16 < m_bits.size();
		if (zeroed)
			for (const auto k : m_keys)
			{
				std::size_t word;
				std::uint64_t bit;
				if (locate(k, word, bit)) m_bits[word] = 0;  // always: every stored key lies in the box
			}
		m_sparse.clear();
		m_keys.clear();
		std::size_t cells = 1;
		for (int i = 0; i < 3; i++)
		{
			m_lo[i] = lo[i];
			m_dim[i] = static_cast<std::size_t>(hi[i]) - lo[i] + 1;
			m_bricks[i] = (m_dim[i] + 3) / 4;
			cells *= m_dim[i];
		}
		m_dense = cells <= kMaxCells;
		const std::size_t words = m_bricks[0] * m_bricks[1] * m_bricks[2];
		if (m_dense && zeroed)
			m_bits.resize(words, 0);
		else if (m_dense)
			m_bits.assign(words, 0);
	}
	bool insert(std::uint64_t key)
	{
		if (!m_dense) return m_sparse.insert(key);
		std::size_t word;
		std::uint64_t bit;
		if (!locate(key, word, bit) || (m_bits[word] & bit)) return false;
		m_bits[word] |= bit;
		m_keys.push_back(key);
		return true;
	}
	bool contains(std::uint64_t key) const
	{
		if (!m_dense) return m_sparse.contains(key);
		std::size_t word;
		std::uint64_t bit;
		return locate(key, word, bit) && (m_bits[word] & bit);
	}
	const std::vector<std::uint64_t>& keys() const { return m_dense ? m_keys : m_sparse.keys(); }

   private:
	static constexpr std::size_t kMaxCells = std::size_t(1) << 24;
	bool locate(std::uint64_t packed, std::size_t& word, std::uint64_t& bit) const
	{
		const auto k = unpackKey(packed);
		const std::size_t x = std::size_t(k[0]) - m_lo[0], y = std::size_t(k[1]) - m_lo[1],
						  z = std::size_t(k[2]) - m_lo[2];
		// Below the box the subtraction wraps to a huge value.
		if (x >= m_dim[0] || y >= m_dim[1] || z >= m_dim[2]) return false;
		word = ((x >> 2) * m_bricks[1] + (y >> 2)) * m_bricks[2] + (z >> 2);
		bit = std::uint64_t(1) << ((x & 3) << 4 | (y & 3) << 2 | (z & 3));
		return true;
	}

	bool m_dense = false;
	std::size_t m_lo[3] = {0, 0, 0}, m_dim[3] = {0, 0, 0}, m_bricks[3] = {0, 0, 0};
	std::vector<std::uint64_t> m_bits;
	std::vector<std::uint64_t> m_keys;
	KeySet m_sparse;
};
}  // namespace avm::detail
