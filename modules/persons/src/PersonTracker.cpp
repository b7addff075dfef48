#include "avm/persons/PersonTracker.h"

#include <algorithm>
#include <iterator>
#include <tuple>

#include "avm/io/PointArchive.h"

namespace avm::persons
{
PersonTracker::PersonTracker(const TrackerOptions& options) : m_options(options) {}

std::vector<std::uint32_t> PersonTracker::update(
	const std::vector<PersonSighting>& sightings, std::size_t frame, double time)
{
	struct Pair
	{
		double distance;
		std::size_t track, sighting;
	};
	std::vector<Pair> pairs;
	for (std::size_t t = 0; t < m_tracks.size(); ++t)
	{
		const auto& track = m_tracks[t];
		const double unseen = std::max(0.0, time - track.lastTime);
		const double gate = std::min(m_options.maxGate, m_options.gate + m_options.gateGrowth * unseen);
		for (std::size_t s = 0; s < sightings.size(); ++s)
		{
			const double d = (sightings[s].position - track.position).norm();
			if (d <= gate) pairs.push_back({d, t, s});
		}
	}
	std::sort(pairs.begin(), pairs.end(),
		[](const Pair& a, const Pair& b)
		{ return std::tie(a.distance, a.track, a.sighting) < std::tie(b.distance, b.track, b.sighting); });

	std::vector<std::uint32_t> ids(sightings.size(), 0);
	std::vector<bool> trackTaken(m_tracks.size(), false);
	const auto record = [&](PersonTrack& track, const PersonSighting& s)
	{
		const double dt = time - track.lastTime;
		track.velocity =
			track.sightings > 0 && dt > 0 ? (s.position - track.position) * (1.0 / dt) : mrpt::math::TPoint3D(0, 0, 0);
		if (track.sightings == 0 || (s.position - track.settledAt).norm() > m_options.stillFraction * meanEdge(s.box))
		{
			track.settledAt = s.position;
			track.settledSince = time;
		}
		track.still = time - track.settledSince >= m_options.stillAfter;
		track.lastFrame = frame;
		track.lastTime = time;
		track.position = s.position;
		track.box = s.box;
		track.bandExtent = s.bandExtent;
		track.shape = s.shape;
		++track.sightings;
	};
	for (const auto& p : pairs)
	{
		if (trackTaken[p.track] || ids[p.sighting] != 0) continue;
		trackTaken[p.track] = true;
		ids[p.sighting] = m_tracks[p.track].id;
		record(m_tracks[p.track], sightings[p.sighting]);
	}
	for (std::size_t s = 0; s < sightings.size(); ++s)
	{
		if (ids[s] != 0) continue;
		PersonTrack track;
		track.id = static_cast<std::uint32_t>(m_tracks.size() + 1);
		track.firstFrame = frame;
		track.firstTime = time;
		record(track, sightings[s]);
		ids[s] = track.id;
		m_tracks.push_back(track);
	}
	return ids;
}

std::vector<PersonTrack> confirmedTracks(const std::vector<PersonTrack>& tracks, std::size_t minSightings)
{
	std::vector<PersonTrack> out;
	std::copy_if(tracks.begin(), tracks.end(), std::back_inserter(out),
		[&](const PersonTrack& t) { return t.sightings >= minSightings; });
	return out;
}

double meanEdge(const mrpt::math::TBoundingBox& box)
{
	const auto edge = box.max - box.min;
	return (edge.x + edge.y + edge.z) / 3.0;
}

void PersonTracker::serializeTo(mrpt::serialization::CArchive& out) const
{
	out.WriteAs<uint32_t>(m_tracks.size());
	for (const auto& t : m_tracks)
	{
		out << t.id << static_cast<uint64_t>(t.firstFrame) << static_cast<uint64_t>(t.lastFrame) << t.firstTime
			<< t.lastTime;
		io::writePoint(out, t.position);
		io::writeBox(out, t.box);
		out << static_cast<uint64_t>(t.sightings);
		io::writePoint(out, t.velocity);
		io::writePoint(out, t.settledAt);
		out << t.settledSince << t.still;
		out.WriteAs<uint32_t>(t.shape.size());
		for (const auto& p : t.shape) out << p.x << p.y << p.z;
		io::writeBox(out, t.bandExtent);
	}
}

void PersonTracker::serializeFrom(mrpt::serialization::CArchive& in, const TrackStreamParts& parts)
{
	m_tracks.resize(in.ReadAs<uint32_t>());
	for (auto& t : m_tracks)
	{
		uint64_t first = 0, last = 0, count = 0;
		in >> t.id >> first >> last >> t.firstTime >> t.lastTime;
		io::readPoint(in, t.position);
		io::readBox(in, t.box);
		in >> count;
		t.firstFrame = first, t.lastFrame = last, t.sightings = count;
		if (parts.motion)
		{
			io::readPoint(in, t.velocity);
			io::readPoint(in, t.settledAt);
			in >> t.settledSince >> t.still;
		}
		else
			t.settledAt = t.position, t.settledSince = t.lastTime;
		// Read point by point: a corrupt count ends the stream, not the memory.
		t.shape.clear();
		for (uint32_t n = parts.shape ? in.ReadAs<uint32_t>() : 0; n > 0; --n)
		{
			mrpt::math::TPoint3Df p;
			in >> p.x >> p.y >> p.z;
			t.shape.push_back(p);
		}
		t.bandExtent = t.box;
		if (parts.bandExtent) io::readBox(in, t.bandExtent);
	}
}
}  // namespace avm::persons
