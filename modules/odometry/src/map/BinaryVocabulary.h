// A bag of binary words for ORB descriptors (no such library is packaged for
// Debian bookworm): a tree of k-majority clusters (k-medians under the
// Hamming distance, as DBoW2 builds its vocabularies), trained on
// descriptors of the run itself, so nothing is downloaded. A descriptor's
// word is the leaf reached by taking the nearest centre at every level.
#pragma once

#include <mrpt/serialization/CArchive.h>

#include <utility>
#include <vector>

#include "../Types.h"

namespace avm::odometry::detail
{
/** Word ids with their L1-normalised term frequencies, sorted by word. */
using BowVector = std::vector<std::pair<int, float>>;

class BinaryVocabulary
{
   public:
	/** Up to branching^depth words. Deterministic: the same descriptors
	 *  always give the same tree. */
	void train(const std::vector<OrbDescriptor>& descriptors, int branching, int depth);
	bool trained() const { return !m_nodes.empty(); }
	int wordCount() const { return m_words; }
	int word(const std::uint8_t* descriptor) const;
	/** The words of a set of descriptors (one per row, CV_8U, 32 bytes). */
	BowVector transform(const cv::Mat& descriptors) const;
	/** 1 - |a - b|_1 / 2 for L1-normalised vectors: 1 for the same words in
	 *  the same proportions, 0 for none in common (DBoW2's L1 score). */
	static double score(const BowVector& a, const BowVector& b);

	void save(mrpt::serialization::CArchive& out) const;
	/** Throws std::runtime_error (badState) on a truncated or corrupt stream. */
	void load(mrpt::serialization::CArchive& in);

   private:
	struct Node
	{
		OrbDescriptor centre{};
		int firstChild = -1;  //!< children are contiguous; -1 for a leaf
		int children = 0;
		int word = -1;  //!< leaves only
	};
	void build(int node, std::vector<int> members, const std::vector<OrbDescriptor>& all, int branching, int levels);

	std::vector<Node> m_nodes;  //!< [0] is the root
	int m_words = 0;
};
}  // namespace avm::odometry::detail
