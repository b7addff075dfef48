#include "KeyframeMap.h"

#include <mrpt/core/bits_math.h>

#include <algorithm>
#include <limits>

#include "../StateStream.h"

namespace avm::odometry::detail
{
LandmarkMap pointsOf(const MapKeyframe& kf)
{
	LandmarkMap points;
	addKeyframePoints(kf.T_cw, kf.descriptors, kf.points, 0, points);
	return points;
}

namespace
{
// The vocabulary is trained once, on the descriptors of the first keyframes
// (about 5000 with the default budget): enough for 1000 words of the scene
// at hand, early enough to index a loss a few seconds into a run.
constexpr std::size_t vocabularyKeyframes = 5;
constexpr int vocabularyBranching = 10, vocabularyDepth = 3;
}  // namespace

void KeyframeMap::add(int id, MapKeyframe kf, int keepFrom)
{
	auto& stored = m_keyframes.emplace(id, std::move(kf)).first->second;
	if (m_vocabulary.trained())
		index(id, stored);
	else if (m_keyframes.size() >= vocabularyKeyframes)
	{
		std::vector<OrbDescriptor> training;
		for (const auto& [kid, k] : m_keyframes)
			for (int r = 0; r < k.descriptors.rows; ++r) training.push_back(descriptorRow(k.descriptors, r));
		m_vocabulary.train(training, vocabularyBranching, vocabularyDepth);
		m_inverted.assign(m_vocabulary.wordCount(), {});
		for (auto& [kid, k] : m_keyframes) index(kid, k);
	}
	while (m_keyframes.size() > std::size_t(m_options->map_max_keyframes) && evictMostRedundant(keepFrom))
	{
	}
}

void KeyframeMap::index(int id, MapKeyframe& kf)
{
	kf.words = m_vocabulary.transform(kf.descriptors);
	for (const auto& [w, weight] : kf.words) m_inverted[w].emplace_back(id, weight);
}

bool KeyframeMap::evictMostRedundant(int keepFrom)
{
	const auto distance = [&](const MapKeyframe& a, const MapKeyframe& b)
	{
		const Eigen::Isometry3d rel = a.T_cw * b.T_cw.inverse();
		return rel.translation().norm() / m_options->keyframe_translation +
			   mrpt::RAD2DEG(Eigen::AngleAxisd(rel.rotation()).angle()) / m_options->keyframe_rotation;
	};
	double closest = std::numeric_limits<double>::infinity();
	int victim = -1;
	for (auto a = m_keyframes.begin(); a != m_keyframes.end() && a->first < keepFrom; ++a)
		for (auto b = std::next(a); b != m_keyframes.end(); ++b)
			if (const double d = distance(a->second, b->second); d < closest)
			{
				closest = d;
				victim = a->first;  // a is the older of the two
			}
	if (victim < 0) return false;
	for (const auto& [w, weight] : m_keyframes.at(victim).words)
	{
		auto& postings = m_inverted[w];
		postings.erase(
			std::find_if(postings.begin(), postings.end(), [&](const auto& p) { return p.first == victim; }));
	}
	m_keyframes.erase(victim);
	return true;
}

void KeyframeMap::updatePose(int id, const Eigen::Isometry3d& T_cw)
{
	if (auto it = m_keyframes.find(id); it != m_keyframes.end()) it->second.T_cw = T_cw;
}

const MapKeyframe* KeyframeMap::find(int id) const
{
	const auto it = m_keyframes.find(id);
	return it == m_keyframes.end() ? nullptr : &it->second;
}

std::vector<KeyframeMap::Candidate> KeyframeMap::candidates(
	const cv::Mat& descriptors, std::size_t n, int newestId) const
{
	std::vector<Candidate> out;
	if (!m_vocabulary.trained())
	{
		for (auto it = std::make_reverse_iterator(m_keyframes.upper_bound(newestId));
			 it != m_keyframes.rend() && out.size() < n; ++it)
			out.push_back({it->first, 0.0});
		return out;
	}
	// Only keyframes sharing a word with the query can score; the sum of the
	// smaller weights of common words is BinaryVocabulary::score.
	std::map<int, double> scores;
	for (const auto& [w, weight] : m_vocabulary.transform(descriptors))
		for (const auto& [id, kfWeight] : m_inverted[w]) scores[id] += std::min(weight, kfWeight);
	for (const auto& [id, s] : scores)
		if (id <= newestId) out.push_back({id, s});
	std::sort(out.begin(), out.end(),
		[](const Candidate& a, const Candidate& b)
		{ return a.score != b.score ? a.score > b.score : a.keyframe > b.keyframe; });
	if (out.size() > n) out.resize(n);
	return out;
}

void KeyframeMap::save(mrpt::serialization::CArchive& out) const
{
	m_vocabulary.save(out);
	out << std::uint32_t(m_keyframes.size());
	for (const auto& [id, kf] : m_keyframes)
	{
		out << std::int32_t(id);
		writePose(out, kf.T_cw);
		out << std::uint32_t(kf.points.size());
		if (!kf.points.empty()) write(out, kf.descriptors.ptr<std::uint8_t>(), kf.points.size() * 32);
		for (const auto& p : kf.points) write(out, p.data(), 3);
	}
}

void KeyframeMap::load(mrpt::serialization::CArchive& in)
{
	BinaryVocabulary vocabulary;
	vocabulary.load(in);
	std::map<int, MapKeyframe> keyframes;
	for (auto n = read<std::uint32_t>(in); n > 0; --n)
	{
		const int id = read<std::int32_t>(in);
		MapKeyframe kf;
		kf.T_cw = readPose(in);
		const auto features = read<std::uint32_t>(in);
		if (features > 1u << 20) throw badState("corrupt odometry state (keyframe " + std::to_string(id) + ")");
		kf.descriptors.create(int(features), 32, CV_8U);
		if (features > 0) read(in, kf.descriptors.ptr<std::uint8_t>(), features * 32);
		kf.points.resize(features);
		for (auto& p : kf.points)
		{
			read(in, p.data(), 3);
			if (!p.allFinite()) throw badState("corrupt odometry state (keyframe " + std::to_string(id) + ")");
		}
		if (!keyframes.emplace(id, std::move(kf)).second)
			throw badState("corrupt odometry state (keyframe " + std::to_string(id) + " twice)");
	}
	m_vocabulary = std::move(vocabulary);
	m_keyframes = std::move(keyframes);
	// The words are a function of the descriptors and the vocabulary.
	m_inverted.assign(m_vocabulary.wordCount(), {});
	if (m_vocabulary.trained())
		for (auto& [id, kf] : m_keyframes) index(id, kf);
}
}  // namespace avm::odometry::detail
