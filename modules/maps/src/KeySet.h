// A flat hash set of packed octree keys for the insertion hot path: open
// addressing with linear probing, cleared per scan in O(inserted), never
// shrinking, so a steady stream of scans allocates nothing.
#pragma once

#include <octomap/OcTreeKey.h>

#include <cstdint>
#include <vector>

namespace avm::detail
{
/** 3 x 16-bit key in one word, +1 so that 0 can mark an empty slot. */
inline std::uint64_t packKey(const octomap::OcTreeKey& k)
{
	return ((std::uint64_t(k[0]) << 32) | (std::uint64_t(k[1]) << 16) | std::uint64_t(k[2])) + 1;
}
inline octomap::OcTreeKey unpackKey(std::uint64_t packed)
{
	const std::uint64_t v = packed - 1;
	return octomap::OcTreeKey(
		static_cast<octomap::key_type>(v >> 32), static_cast<octomap::key_type>((v >> 16) & 0xFFFF),
		static_cast<octomap::key_type>(v & 0xFFFF));
}

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
	std::size_t size() const { return m_keys.size(); }

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
