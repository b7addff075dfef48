#include "SurfaceSketch.h"

#include <algorithm>
#include <vector>

#include "OcTreeKeys.h"

namespace avm::detail
{
namespace
{
/** floor(a / b) for b > 0. */
int floorDiv(int a, int b) { return a >= 0 ? a / b : -((-a + b - 1) / b); }
}  // namespace

std::uint64_t SurfaceSketch::lowKeyOf(std::uint64_t highKey) const { return coarserKeyOf(highKey, m_ratio); }

unsigned SurfaceSketch::bitOf(std::uint64_t highKey) const
{
	const auto h = unpackKey(highKey);
	const int r = static_cast<int>(m_ratio);
	unsigned bit = 0;
	for (int i = 0; i < 3; i++)
	{
		const int rel = static_cast<int>(h[i]) - kKeyOffset;
		bit = bit * m_ratio + static_cast<unsigned>(rel - floorDiv(rel, r) * r);
	}
	return bit;
}

std::uint64_t SurfaceSketch::highKeyOf(std::uint64_t lowKey, unsigned bit) const
{
	const auto l = unpackKey(lowKey);
	const unsigned offset[3] = {bit / (m_ratio * m_ratio), (bit / m_ratio) % m_ratio, bit % m_ratio};
	octomap::OcTreeKey h;
	for (int i = 0; i < 3; i++)
		h[i] = static_cast<octomap::key_type>(
			(static_cast<int>(l[i]) - kKeyOffset) * static_cast<int>(m_ratio) + kKeyOffset + static_cast<int>(offset[i]));
	return packKey(h);
}

void SurfaceSketch::markHighVoxel(std::uint64_t highKey)
{
	m_bits[lowKeyOf(highKey)] |= std::uint64_t(1) << bitOf(highKey);
}

std::uint64_t SurfaceSketch::take(std::uint64_t lowKey)
{
	const auto it = m_bits.find(lowKey);
	if (it == m_bits.end()) return 0;
	const auto bits = it->second;
	m_bits.erase(it);
	return bits;
}

void SurfaceSketch::set(std::uint64_t lowKey, std::uint64_t bits)
{
	if (bits == 0)
		m_bits.erase(lowKey);
	else
		m_bits[lowKey] = bits;
}

std::size_t SurfaceSketch::memoryBytes() const
{
	// A node of the hash map (key, value, next pointer, cached hash) and one
	// bucket per entry (the container's maximum load factor). Counted from
	// the entries, as octomap's memoryUsage() is from the nodes, not from
	// bucket_count(): that depends on the map's history (growth, erasures,
	// prune's rehash), so a map read back from a checkpoint would report
	// other bytes than the same map never interrupted.
	return m_bits.size() * (2 * sizeof(std::uint64_t) + 3 * sizeof(void*));
}

void SurfaceSketch::serializeTo(mrpt::serialization::CArchive& out) const
{
	// In key order: the same map serializes to the same bytes.
	std::vector<std::pair<std::uint64_t, std::uint64_t>> sorted(m_bits.begin(), m_bits.end());
	std::sort(sorted.begin(), sorted.end());
	out.WriteAs<uint32_t>(m_ratio);
	out.WriteAs<uint64_t>(sorted.size());
	for (const auto& [key, bits] : sorted) out << key << bits;
}

void SurfaceSketch::serializeFrom(mrpt::serialization::CArchive& in)
{
	m_ratio = in.ReadAs<uint32_t>();
	const auto n = in.ReadAs<uint64_t>();
	m_bits.clear();
	for (uint64_t i = 0; i < n; i++)
	{
		std::uint64_t key = 0, bits = 0;
		in >> key >> bits;
		m_bits[key] = bits;
	}
}
}  // namespace avm::detail
