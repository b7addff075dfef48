#include "BinaryVocabulary.h"

#include <algorithm>
#include <climits>
#include <cmath>
#include <limits>
#include <random>

#include "../StateStream.h"

namespace avm::odometry::detail
{
namespace
{
/** Index of the centre nearest to d (the first of equally near ones). */
int nearest(const std::uint8_t* d, const std::vector<OrbDescriptor>& centres)
{
	int best = 0, bestDist = INT_MAX;
	for (int c = 0; c < int(centres.size()); ++c)
		if (const int dist = hamming(d, centres[c].data()); dist < bestDist)
		{
			bestDist = dist;
			best = c;
		}
	return best;
}

/** Bitwise majority of the members (ties give 0): the binary k-medians centre. */
OrbDescriptor majority(const std::vector<int>& members, const std::vector<OrbDescriptor>& all)
{
	std::array<int, 256> ones{};
	for (const int m : members)
		for (int byte = 0; byte < 32; ++byte)
			for (int bit = 0; bit < 8; ++bit) ones[byte * 8 + bit] += (all[m][byte] >> bit) & 1;
	OrbDescriptor c{};
	for (int bit = 0; bit < 256; ++bit)
		if (2 * ones[bit] > int(members.size())) c[bit / 8] |= std::uint8_t(1u << (bit % 8));
	return c;
}

/** Same seed for every tree: training is reproducible run to run. */
constexpr unsigned trainingSeed = 5489u;
constexpr int kMedianIterations = 10;
}  // namespace

void BinaryVocabulary::train(const std::vector<OrbDescriptor>& descriptors, int branching, int depth)
{
	m_nodes.assign(1, Node{});
	m_words = 0;
	std::vector<int> all(descriptors.size());
	for (int i = 0; i < int(all.size()); ++i) all[i] = i;
	build(0, std::move(all), descriptors, branching, depth);
	if (m_words == 0) m_nodes.clear();
}

void BinaryVocabulary::build(
	int node, std::vector<int> members, const std::vector<OrbDescriptor>& all, int branching, int levels)
{
	if (levels == 0 || int(members.size()) <= 1)
	{
		if (!members.empty()) m_nodes[node].word = m_words++;
		return;
	}
	// k-means++ seeding: each next centre drawn with probability growing with
	// the squared distance to the nearest centre so far.
	std::mt19937 rng(trainingSeed + unsigned(node));
	const int k = std::min<int>(branching, int(members.size()));
	std::vector<OrbDescriptor> centres{all[members[rng() % members.size()]]};
	std::vector<double> d2(members.size(), std::numeric_limits<double>::infinity());
	while (int(centres.size()) < k)
	{
		double total = 0;
		for (std::size_t i = 0; i < members.size(); ++i)
		{
			const double d = hamming(all[members[i]].data(), centres.back().data());
			total += d2[i] = std::min(d2[i], d * d);
		}
		if (total == 0) break;  // the rest duplicates a centre
		double r = double(rng()) / 4294967296.0 * total;
		std::size_t pick = 0;
		while (pick + 1 < members.size() && (r -= d2[pick]) >= 0) ++pick;
		centres.push_back(all[members[pick]]);
	}
	std::vector<int> assignment(members.size(), -1);
	std::vector<std::vector<int>> clusters;
	for (int it = 0; it < kMedianIterations; ++it)
	{
		bool changed = false;
		clusters.assign(centres.size(), {});
		for (std::size_t i = 0; i < members.size(); ++i)
		{
			const int c = nearest(all[members[i]].data(), centres);
			changed |= c != assignment[i];
			assignment[i] = c;
			clusters[c].push_back(members[i]);
		}
		if (!changed) break;
		for (std::size_t c = 0; c < centres.size(); ++c)
			if (!clusters[c].empty()) centres[c] = majority(clusters[c], all);
	}
	std::vector<int> used;
	for (int c = 0; c < int(centres.size()); ++c)
		if (!clusters[c].empty()) used.push_back(c);
	const int first = int(m_nodes.size());
	m_nodes[node].firstChild = first;
	m_nodes[node].children = int(used.size());
	m_nodes.resize(m_nodes.size() + used.size());
	for (int i = 0; i < int(used.size()); ++i)
	{
		m_nodes[first + i].centre = centres[used[i]];
		build(first + i, std::move(clusters[used[i]]), all, branching, levels - 1);
	}
}

int BinaryVocabulary::word(const std::uint8_t* descriptor) const
{
	int node = 0;
	while (m_nodes[node].firstChild >= 0)
	{
		const Node& n = m_nodes[node];
		int best = n.firstChild, bestDist = INT_MAX;
		for (int c = n.firstChild; c < n.firstChild + n.children; ++c)
			if (const int d = hamming(descriptor, m_nodes[c].centre.data()); d < bestDist)
			{
				bestDist = d;
				best = c;
			}
		node = best;
	}
	return m_nodes[node].word;
}

BowVector BinaryVocabulary::transform(const cv::Mat& descriptors) const
{
	BowVector v;
	if (!trained() || descriptors.rows == 0) return v;
	std::vector<int> words(descriptors.rows);
	for (int i = 0; i < descriptors.rows; ++i) words[i] = word(descriptors.ptr<std::uint8_t>(i));
	std::sort(words.begin(), words.end());
	const float share = 1.0f / float(words.size());
	for (const int w : words)
	{
		if (v.empty() || v.back().first != w) v.emplace_back(w, 0.0f);
		v.back().second += share;
	}
	return v;
}

double BinaryVocabulary::score(const BowVector& a, const BowVector& b)
{
	// For non-negative vectors that each sum to 1, 1 - |a - b|_1 / 2 is the
	// sum of the smaller weight of every common word.
	double s = 0;
	for (auto i = a.begin(), j = b.begin(); i != a.end() && j != b.end();)
	{
		if (i->first < j->first)
			++i;
		else if (j->first < i->first)
			++j;
		else
			s += std::min((i++)->second, (j++)->second);
	}
	return s;
}

void BinaryVocabulary::save(mrpt::serialization::CArchive& out) const
{
	out << std::uint32_t(m_nodes.size()) << std::int32_t(m_words);
	for (const auto& n : m_nodes)
	{
		write(out, n.centre.data(), n.centre.size());
		out << std::int32_t(n.firstChild) << std::int32_t(n.children) << std::int32_t(n.word);
	}
}

void BinaryVocabulary::load(mrpt::serialization::CArchive& in)
{
	const auto count = read<std::uint32_t>(in);
	const int words = read<std::int32_t>(in);
	std::vector<Node> nodes(count);
	for (auto& n : nodes)
	{
		read(in, n.centre.data(), n.centre.size());
		n.firstChild = read<std::int32_t>(in);
		n.children = read<std::int32_t>(in);
		n.word = read<std::int32_t>(in);
	}
	// Every child range inside the tree and below its parent, every leaf a word:
	// word() then always ends at a leaf.
	for (std::size_t i = 0; i < nodes.size(); ++i)
	{
		const Node& n = nodes[i];
		const bool leaf = n.firstChild < 0;
		if (leaf ? (n.word < 0 || n.word >= words)
				 : (n.firstChild <= int(i) || n.children < 1 || n.firstChild + n.children > int(count)))
			throw badState("corrupt odometry state (place vocabulary node " + std::to_string(i) + ")");
	}
	if ((count == 0) != (words == 0)) throw badState("corrupt odometry state (place vocabulary)");
	m_nodes = std::move(nodes);
	m_words = words;
}
}  // namespace avm::odometry::detail
