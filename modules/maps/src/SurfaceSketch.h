// Where inside each low voxel the surface was seen: one bit per high voxel of
// the low voxel (a 0.20 m voxel holds 4 x 4 x 4 = 64 voxels of 0.05 m), set by
// the scan endpoints that land in low-tree space, and by the occupied high
// voxels of space that leaves a region; cleared where a later depth image
// sees through the voxel (a single high-resolution map frees what its rays cross). A few bytes per occupied low voxel
// keep the shape a low voxel lost, so that when a person's region reaches
// it the high tree gets the surface back where it was (a wall 5 cm thick), not
// a solid 20 cm block.
#pragma once

#include <mrpt/serialization/CArchive.h>

#include <cstddef>
#include <cstdint>
#include <algorithm>
#include <array>
#include <optional>
#include <vector>

#include "OcTreeKeys.h"

namespace avm::detail
{
class SurfaceSketch
{
   public:
	/** `ratio`: high voxels per low voxel edge; the sketch is kept only when
	 *  ratio^3 <= 64 (usable()). */
	explicit SurfaceSketch(unsigned ratio = 4) : m_ratio(ratio) {}

	bool usable() const { return m_ratio >= 2 && m_ratio * m_ratio * m_ratio <= 64; }
	unsigned ratio() const { return m_ratio; }

	/** What a scan saw: the high voxels (packed high-tree keys, KeySet.h)
	 *  that held surface, and the low voxels seen with no surface in them that
	 *  the sketch keeps. Low voxels new to the sketch join its sorted entries
	 *  in one merge a scan: one at a time, each moved every entry after it,
	 *  a cost that grew with the map. */
	void markScan(const std::vector<std::uint64_t>& surfaceHighKeys, const std::vector<std::uint64_t>& seenLowKeys);
	/** The low voxel's bits (in bitAtOffset's order), forgotten by the
	 *  sketch; nothing when the sketch never saw the low voxel (no bits: the
	 *  surfaces it saw have all been seen through since). */
	std::optional<std::uint64_t> take(std::uint64_t lowKey);
	/** Replaces the low voxel's bits (0 forgets it). */
	void set(std::uint64_t lowKey, std::uint64_t bits);

	/** The low voxel of a high key, and the high key of a low voxel's bit. */
	std::uint64_t lowKeyOf(std::uint64_t highKey) const;
	std::uint64_t highKeyOf(std::uint64_t lowKey, unsigned bit) const;
	unsigned bitOf(std::uint64_t highKey) const;
	/** The bit order: the bit of the high voxel at offset (x, y, z) in its
	 *  low voxel (each 0 .. ratio - 1) is (x * ratio + y) * ratio + z;
	 *  offsetOfBit is its inverse. */
	unsigned bitAtOffset(const std::array<unsigned, 3>& offset) const
	{
		return (offset[0] * m_ratio + offset[1]) * m_ratio + offset[2];
	}
	std::array<unsigned, 3> offsetOfBit(unsigned bit) const
	{
		return {bit / (m_ratio * m_ratio), (bit / m_ratio) % m_ratio, bit % m_ratio};
	}

	/** Replaces the bits of each low voxel of `lowKeys` by `update(lowKey,
	 *  bits)`; the others are not visited. A low voxel left with no bits is
	 *  kept: its surface has gone, which is not the same as never having been
	 *  seen. What a frame can change lies around the camera: visiting only
	 *  there keeps a frame's cost that of the space in reach, however much of
	 *  a building the sessions before it mapped. */
	template <typename Update>
	void updateBitsWithin(const KeyRange& lowKeys, Update&& update)
	{
		if (lowKeys.empty()) return;
		// Packed keys sort as (x, y, z) triples: the range's entries of one x
		// lie between its (x, lowest y, lowest z) and (x, highest y, highest z).
		for (unsigned x = lowKeys.lo[0]; x < lowKeys.hi[0]; ++x)
		{
			const std::uint64_t last = avm::packKey(x, lowKeys.hi[1] - 1, lowKeys.hi[2] - 1);
			for (auto it = find(avm::packKey(x, lowKeys.lo[1], lowKeys.lo[2]));
				 it != m_entries.end() && it->lowKey <= last; ++it)
			{
				const unsigned z = unpackAxis(it->lowKey, 2);
				if (z >= lowKeys.lo[2] && z < lowKeys.hi[2]) it->bits = update(it->lowKey, it->bits);
			}
		}
	}

	/** Forgets the low voxels for which `keep(lowKey, bits)` is false. */
	template <typename Keep>
	void prune(Keep&& keep)
	{
		const auto gone =
			std::remove_if(m_entries.begin(), m_entries.end(), [&](const Entry& e) { return !keep(e.lowKey, e.bits); });
		m_entries.erase(gone, m_entries.end());
		m_entries.shrink_to_fit();
	}

	std::size_t size() const { return m_entries.size(); }
	/** Bytes of the entries, from their count only: the same sketch gives the
	 *  same figure whatever its history (a vector's spare capacity depends on
	 *  how it grew). */
	std::size_t memoryBytes() const { return m_entries.size() * sizeof(Entry); }

	void serializeTo(mrpt::serialization::CArchive& out) const;
	void serializeFrom(mrpt::serialization::CArchive& in);

   private:
	// Sorted by low key: 16 bytes an entry, where a hash map spends 40 (its
	// node, next pointer, cached hash and bucket); a frame adds few entries
	// (surfaces mostly land in low voxels already seen), so the inserts that
	// keep the order cost less than the hashing they replace.
	struct Entry
	{
		std::uint64_t lowKey, bits;
	};
	/** The low voxel's entry, made (without bits) if there is none. */
	std::uint64_t& entryOf(std::uint64_t lowKey);
	std::vector<Entry>::iterator find(std::uint64_t lowKey);

	unsigned m_ratio;
	std::vector<Entry> m_entries;
};
}  // namespace avm::detail
