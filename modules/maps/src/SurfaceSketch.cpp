#include "SurfaceSketch.h"

#include <algorithm>
#include <iterator>
#include <stdexcept>

#include "OcTreeKeys.h"

namespace avm::detail
{
std::uint64_t SurfaceSketch::lowKeyOf(std::uint64_t highKey) const { return coarserKeyOf(highKey, m_ratio); }

unsigned SurfaceSketch::bitOf(std::uint64_t highKey) const
{
	const auto h = unpackKey(highKey);
	return bitAtOffset({placeInCoarser(h[0], m_ratio), placeInCoarser(h[1], m_ratio), placeInCoarser(h[2], m_ratio)});
}

std::uint64_t SurfaceSketch::highKeyOf(std::uint64_t lowKey, unsigned bit) const
{
	const auto l = unpackKey(lowKey);
	const auto offset = offsetOfBit(bit);
	octomap::OcTreeKey h;
	for (int i = 0; i < 3; i++) h[i] = static_cast<octomap::key_type>(firstFinerKey(l[i], m_ratio) + offset[i]);
	return packKey(h);
}

std::vector<SurfaceSketch::Entry>::iterator SurfaceSketch::find(std::uint64_t lowKey)
{
	return std::lower_bound(
		m_entries.begin(), m_entries.end(), lowKey, [](const Entry& e, std::uint64_t k) { return e.lowKey < k; });
}

std::uint64_t& SurfaceSketch::entryOf(std::uint64_t lowKey)
{
	auto it = find(lowKey);
	if (it == m_entries.end() || it->lowKey != lowKey) it = m_entries.insert(it, Entry{lowKey, 0});
	return it->bits;
}

void SurfaceSketch::markScan(
	const std::vector<std::uint64_t>& surfaceHighKeys, const std::vector<std::uint64_t>& seenLowKeys)
{
	const auto byKey = [](const Entry& a, const Entry& b) { return a.lowKey < b.lowKey; };
	std::vector<Entry> fresh;
	const auto mark = [&](std::uint64_t lowKey, std::uint64_t bits)
	{
		if (const auto it = find(lowKey); it != m_entries.end() && it->lowKey == lowKey)
			it->bits |= bits;
		else
			fresh.push_back({lowKey, bits});
	};
	for (const auto h : surfaceHighKeys) mark(lowKeyOf(h), std::uint64_t(1) << bitOf(h));
	for (const auto l : seenLowKeys) mark(l, 0);
	if (fresh.empty()) return;
	// A new low voxel is marked once for each of its high voxels: one entry
	// with all their bits.
	std::sort(fresh.begin(), fresh.end(), byKey);
	auto last = fresh.begin();
	for (auto it = std::next(fresh.begin()); it != fresh.end(); ++it)
		if (it->lowKey == last->lowKey)
			last->bits |= it->bits;
		else
			*++last = *it;
	fresh.erase(std::next(last), fresh.end());
	const auto before = static_cast<std::ptrdiff_t>(m_entries.size());
	m_entries.insert(m_entries.end(), fresh.begin(), fresh.end());
	std::inplace_merge(m_entries.begin(), m_entries.begin() + before, m_entries.end(), byKey);
}

std::optional<std::uint64_t> SurfaceSketch::take(std::uint64_t lowKey)
{
	const auto it = find(lowKey);
	if (it == m_entries.end() || it->lowKey != lowKey) return std::nullopt;
	const auto bits = it->bits;
	m_entries.erase(it);
	return bits;
}

void SurfaceSketch::set(std::uint64_t lowKey, std::uint64_t bits)
{
	if (bits != 0)
		entryOf(lowKey) = bits;
	else if (const auto it = find(lowKey); it != m_entries.end() && it->lowKey == lowKey)
		m_entries.erase(it);
}

void SurfaceSketch::serializeTo(mrpt::serialization::CArchive& out) const
{
	out.WriteAs<uint32_t>(m_ratio);
	out.WriteAs<uint64_t>(m_entries.size());
	for (const auto& e : m_entries) out << e.lowKey << e.bits;
}

void SurfaceSketch::serializeFrom(mrpt::serialization::CArchive& in)
{
	m_ratio = in.ReadAs<uint32_t>();
	const auto n = in.ReadAs<uint64_t>();
	m_entries.clear();
	for (uint64_t i = 0; i < n; i++)
	{
		Entry e{};
		in >> e.lowKey >> e.bits;
		// Written in key order; a damaged stream must not break the order.
		if (!m_entries.empty() && e.lowKey <= m_entries.back().lowKey)
			throw std::runtime_error("SurfaceSketch: entries out of order in the stream");
		m_entries.push_back(e);
	}
}
}  // namespace avm::detail
