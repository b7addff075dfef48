// The keyframes of the whole run, kept through tracking loss for
// relocalisation: each with its pose, its features' descriptors and their
// points (measured depth, camera frame), and its bag of words in an inverted
// index for place recognition.
//
// Bounded memory: keyframes come at the odometry's keyframe spacing (motion,
// rotation, overlap), at most map_max_keyframes of them (about 70 kB each with
// 1000 features). When a keyframe would exceed the cap, the most redundant
// one goes: of the two keyframes closest to each other (translation over
// keyframe_translation plus rotation over keyframe_rotation), the older,
// never the newest. A map that keeps revisiting one room stays spread over
// it rather than forgetting its beginning.
#pragma once

#include <Eigen/Geometry>
#include <mrpt/serialization/CArchive.h>

#include <limits>
#include <map>
#include <vector>

#include "../Types.h"
#include "../frontend/FeatureFrontend.h"
#include "BinaryVocabulary.h"
#include "avm/odometry/TOdometryOptions.h"

namespace avm::odometry::detail
{
struct MapKeyframe
{
	Eigen::Isometry3d T_cw;
	cv::Mat descriptors;                  //!< one ORB descriptor per row (CV_8U, 32 bytes)
	std::vector<Eigen::Vector3d> points;  //!< [m] camera optical frame, from the keyframe's depth
	BowVector words;                      //!< from descriptors, once the vocabulary exists
};

/** A keyframe's own points in the world, as landmarks numbered by feature index. */
LandmarkMap pointsOf(const MapKeyframe& kf);

class KeyframeMap
{
   public:
	explicit KeyframeMap(const TOdometryOptions& options) : m_options(&options) {}

	/** Adds the keyframe `id` (ids increase); trains the vocabulary on the
	 *  first keyframes once there are enough, then keeps the cap, never
	 *  evicting a keyframe of id keepFrom or newer (those still in use). */
	void add(int id, MapKeyframe kf, int keepFrom);
	/** A keyframe's pose after the window bundle adjustment moved it. */
	void updatePose(int id, const Eigen::Isometry3d& T_cw);
	const MapKeyframe* find(int id) const;
	std::size_t size() const { return m_keyframes.size(); }

	struct Candidate
	{
		int keyframe;
		double score;  //!< BinaryVocabulary::score; 0 before the vocabulary exists
	};
	/** Up to n keyframes most like these descriptors, best first (of equal
	 *  scores the newest), of ids up to `newestId`. Before the vocabulary is
	 *  trained, the newest n. */
	std::vector<Candidate> candidates(
		const cv::Mat& descriptors, std::size_t n, int newestId = std::numeric_limits<int>::max()) const;
	bool trained() const { return m_vocabulary.trained(); }
	/** Every keyframe, by id. */
	const std::map<int, MapKeyframe>& keyframes() const { return m_keyframes; }

	void save(mrpt::serialization::CArchive& out) const;
	/** Throws std::runtime_error (badState) on a truncated or corrupt stream,
	 *  leaving the map as it was. */
	void load(mrpt::serialization::CArchive& in);

   private:
	void index(int id, MapKeyframe& kf);
	/** Whether a keyframe older than keepFrom could go. */
	bool evictMostRedundant(int keepFrom);

	const TOdometryOptions* m_options;       //!< a pointer: a map loaded aside replaces the state by assignment
	std::map<int, MapKeyframe> m_keyframes;  //!< by id: iteration in id order keeps runs reproducible
	BinaryVocabulary m_vocabulary;
	/** Per word, the keyframes holding it and its weight there (ascending id). */
	std::vector<std::vector<std::pair<int, float>>> m_inverted;
};
}  // namespace avm::odometry::detail
