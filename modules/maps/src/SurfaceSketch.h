// Where inside each low voxel the surface was seen: one bit per high voxel of
// the low voxel (a 0.20 m voxel holds 4 x 4 x 4 = 64 voxels of 0.05 m), set by
// the scan endpoints that land in low-tree space, and by the occupied high
// voxels of space that leaves a region. A few bytes per occupied low voxel
// keep the shape a coarse voxel lost, so that when a person's region reaches
// it the high tree gets the surface back where it was (a wall 5 cm thick), not
// a solid 20 cm block.
#pragma once

#include <mrpt/serialization/CArchive.h>

#include <cstddef>
#include <cstdint>
#include <iterator>
#include <unordered_map>

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

	/** The high voxel (packed high-tree key, KeySet.h) held surface. */
	void markHighVoxel(std::uint64_t highKey);
	/** The low voxel's bits (bit (x * ratio + y) * ratio + z for the high
	 *  voxel at offset x, y, z), forgotten by the sketch; 0 if none. */
	std::uint64_t take(std::uint64_t lowKey);
	/** Replaces the low voxel's bits (0 forgets it). */
	void set(std::uint64_t lowKey, std::uint64_t bits);

	/** The low voxel of a high key, and the high key of a low voxel's bit. */
	std::uint64_t lowKeyOf(std::uint64_t highKey) const;
	std::uint64_t highKeyOf(std::uint64_t lowKey, unsigned bit) const;
	unsigned bitOf(std::uint64_t highKey) const;

	/** Forgets the low voxels for which `keep(lowKey)` is false. */
	template <typename Keep>
	void prune(Keep&& keep)
	{
		for (auto it = m_bits.begin(); it != m_bits.end();)
			it = keep(it->first) ? std::next(it) : m_bits.erase(it);
		m_bits.rehash(0);
	}

	std::size_t size() const { return m_bits.size(); }
	/** Bytes of the entries as a hash map holds them, from their count only:
	 *  the same sketch gives the same figure whatever its history. */
	std::size_t memoryBytes() const;

	void serializeTo(mrpt::serialization::CArchive& out) const;
	void serializeFrom(mrpt::serialization::CArchive& in);

   private:
	unsigned m_ratio;
	std::unordered_map<std::uint64_t, std::uint64_t> m_bits;
};
}  // namespace avm::detail
