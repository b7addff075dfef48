#include "FeatureFrontend.h"

#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>

#include "avm/io/DepthEdge.h"

namespace avm::odometry::detail
{
namespace
{
/** Depth at a pixel if it is valid and not on a depth discontinuity (the 3x3
 *  neighbourhood is complete and its range small relative to the depth). */
std::optional<double> stableDepth(const cv::Mat& depth, int u, int v, const TOdometryOptions& o)
{
	if (u < 1 || v < 1 || u >= depth.cols - 1 || v >= depth.rows - 1) return std::nullopt;
	const float d = depth.at<float>(v, u);
	if (!(d >= o.min_depth && d <= o.max_depth)) return std::nullopt;
	const auto depthAt = [&](int x, int y) { return depth.at<float>(y, x); };
	if (io::onDepthEdge(depthAt, u, v, depth.cols, depth.rows, o.depth_edge_ratio)) return std::nullopt;
	return d;
}

/** Depth beyond which a box's pixels are background: the median depth of the
 *  box's central part (where the person is) plus `band`. Nothing when band is
 *  0 or the centre has no depth: then the whole box is masked. */
std::optional<float> personBackgroundDepth(const cv::Mat& depth, const cv::Rect& box, double band)
{
	if (band <= 0) return std::nullopt;
	const cv::Rect centre = cv::Rect(box.x + box.width / 4, box.y + box.height / 4, box.width / 2, box.height / 2) &
							cv::Rect(0, 0, depth.cols, depth.rows);
	std::vector<float> values;
	for (int v = centre.y; v < centre.y + centre.height; v += 2)
		for (int u = centre.x; u < centre.x + centre.width; u += 2)
			if (const float d = depth.at<float>(v, u); d > 0) values.push_back(d);
	if (values.size() < 20) return std::nullopt;
	std::nth_element(values.begin(), values.begin() + values.size() / 2, values.end());
	return values[values.size() / 2] + float(band);
}
}  // namespace

FeatureFrontend::FeatureFrontend(const TOdometryOptions& options)
	: m_options(options),
	  m_orb(2 * options.num_features, static_cast<float>(options.pyramid_scale), options.pyramid_levels,
		  options.fast_threshold)
{
}

cv::Mat FeatureFrontend::personMask(const cv::Mat& depth, const std::vector<cv::Rect>& boxes) const
{
	const auto& o = m_options;
	cv::Mat mask = cv::Mat::zeros(depth.size(), CV_8U);
	for (const auto& box : boxes)
	{
		const cv::Rect grown = cv::Rect(box.x - o.person_box_margin, box.y - o.person_box_margin,
								   box.width + 2 * o.person_box_margin, box.height + 2 * o.person_box_margin) &
							   cv::Rect(0, 0, mask.cols, mask.rows);
		if (grown.empty()) continue;
		const auto far = personBackgroundDepth(depth, box, o.person_depth_band);
		if (!far)
		{
			mask(grown).setTo(255);
			continue;
		}
		// Only the person and whatever is in front: the background seen around
		// and behind them in the box stays usable.
		cv::Mat roiMask = mask(grown);
		roiMask.setTo(255, depth(grown) < *far);
	}
	return mask;
}

FrameFeatures FeatureFrontend::extract(const cv::Mat& grey, const cv::Mat& depth, const io::DepthCamera& K,
	const std::vector<cv::Rect>& excluded, std::vector<cv::KeyPoint>* masked,
	mrpt::system::CTimeLogger* stageTimer) const
{
	const auto& o = m_options;
	FrameFeatures f;
	f.K = K;
	f.imageSize = grey.size();

	const cv::Mat people = personMask(depth, excluded);
	cv::Mat mask = depth > 0;
	mask.setTo(0, people);
	std::vector<cv::KeyPoint> detected;
	OrbExtractor::Pyramid pyramid;
	{
		std::optional<mrpt::system::CTimeLoggerEntry> t;
		if (stageTimer) t.emplace(*stageTimer, "1.1 ORB detection");
		pyramid = m_orb.build(grey, mask);
		detected = m_orb.detect(pyramid);
	}
	if (masked)
	{
		masked->clear();
		if (!excluded.empty()) *masked = m_orb.detect(m_orb.withMask(pyramid, people & (depth > 0)));
	}

	// Bucketing: the strongest features of every grid cell first, so texture-rich
	// corners do not take the whole budget; the rest of the budget by strength.
	const int cells = o.grid_cols * o.grid_rows;
	const std::size_t perCell = static_cast<std::size_t>((o.num_features + cells - 1) / cells);
	std::vector<std::vector<int>> grid(cells);
	std::vector<double> depthOf(detected.size(), 0);  // [m] of a candidate with a stable depth
	for (int i = 0; i < int(detected.size()); ++i)
	{
		const cv::KeyPoint& kp = detected[std::size_t(i)];
		const auto d = stableDepth(depth, cvRound(kp.pt.x), cvRound(kp.pt.y), o);
		if (!d) continue;
		depthOf[std::size_t(i)] = *d;
		const int c = std::min(o.grid_cols - 1, int(kp.pt.x * o.grid_cols / grey.cols));
		const int r = std::min(o.grid_rows - 1, int(kp.pt.y * o.grid_rows / grey.rows));
		grid[r * o.grid_cols + c].push_back(i);
	}
	std::vector<int> kept, spare;
	const auto stronger = [&](int a, int b)
	{ return detected[std::size_t(a)].response > detected[std::size_t(b)].response; };
	for (auto& cell : grid)
	{
		std::sort(cell.begin(), cell.end(), stronger);
		for (std::size_t i = 0; i < cell.size(); ++i) (i < perCell ? kept : spare).push_back(cell[i]);
	}
	if (kept.size() < std::size_t(o.num_features))
	{
		std::sort(spare.begin(), spare.end(), stronger);
		const std::size_t more = std::min(spare.size(), std::size_t(o.num_features) - kept.size());
		kept.insert(kept.end(), spare.begin(), spare.begin() + more);
	}
	if (kept.empty()) return f;
	// In ORB's order for given features (by pyramid level, stable within
	// one), which the matching's tie-breaks and the landmark ids follow.
	std::stable_sort(kept.begin(), kept.end(),
		[&](int a, int b) { return detected[std::size_t(a)].octave < detected[std::size_t(b)].octave; });
	f.keypoints.reserve(kept.size());
	for (int k : kept) f.keypoints.push_back(detected[std::size_t(k)]);
	// Only the kept features are described (half the candidates): on the
	// detection's pyramid, so the rows are those a description with the
	// detection would give.
	{
		std::optional<mrpt::system::CTimeLoggerEntry> t;
		if (stageTimer) t.emplace(*stageTimer, "1.2 ORB description");
		f.descriptors = m_orb.describe(pyramid, f.keypoints);
	}
	f.points.reserve(f.keypoints.size());
	for (int k : kept)
	{
		const cv::KeyPoint& kp = detected[std::size_t(k)];
		f.points.push_back(K.opticalPointOf(kp.pt.x, kp.pt.y, depthOf[std::size_t(k)]));
	}
	return f;
}

namespace
{
/** The features bucketed by cells of the search radius, in one array (a
 *  counting sort, feature order kept within a cell): a landmark's search reads
 *  the few cells its window overlaps, with their pixels at hand. */
class ProjectionSearch
{
   public:
	ProjectionSearch(const FrameFeatures& frame, const TOdometryOptions& options)
		: m_frame(frame),
		  m_options(options),
		  m_cellSize(options.search_radius),
		  m_cols(int(std::ceil(frame.imageSize.width / m_cellSize)) + 1),
		  m_rows(int(std::ceil(frame.imageSize.height / m_cellSize)) + 1),
		  m_cellStart(std::size_t(m_cols * m_rows) + 1, 0),
		  m_features(frame.keypoints.size())
	{
		const auto cellOf = [&](const cv::Point2f& p)
		{ return int(p.y / m_cellSize) * m_cols + int(p.x / m_cellSize); };
		for (const auto& kp : frame.keypoints) ++m_cellStart[std::size_t(cellOf(kp.pt)) + 1];
		for (std::size_t c = 1; c < m_cellStart.size(); ++c) m_cellStart[c] += m_cellStart[c - 1];
		std::vector<int> next(m_cellStart.begin(), m_cellStart.end() - 1);
		for (int i = 0; i < int(frame.keypoints.size()); ++i)
		{
			const auto& p = frame.keypoints[i].pt;
			m_features[std::size_t(next[std::size_t(cellOf(p))]++)] = {p.x, p.y, frame.descriptorData(i), i};
		}
	}

	/** best[feature] = (distance, landmark): one landmark per feature, the
	 *  closest; of equally close ones the newest (largest id), so that the
	 *  result does not depend on the map's iteration order (which a reloaded
	 *  map does not keep). Always inlined: the popcount instruction's copy
	 *  below is this search built for it. */
	template <bool kPopcount>
	[[gnu::always_inline]] inline void bestLandmarks(
		const LandmarkMap& landmarks, const Eigen::Isometry3d& T_cw, std::vector<std::pair<int, int>>& best) const
	{
		const auto& o = m_options;
		const double r = o.search_radius, r2 = r * r;
		const cv::Size size = m_frame.imageSize;
		for (auto it = landmarks.begin(); it != landmarks.end(); ++it)
		{
			// The table's nodes lie apart in memory, and most landmarks project
			// outside the image and cost little more than their node's cache
			// miss: the next node is fetched while this one is searched.
			if (const auto next = std::next(it); next != landmarks.end()) __builtin_prefetch(&*next);
			const auto& [id, lm] = *it;
			const Eigen::Vector3d pc = T_cw * lm.position;
			if (pc.z() < o.min_depth) continue;
			const Eigen::Vector2d px = m_frame.K.opticalPixelOf(pc);
			const double u = px.x(), v = px.y();
			if (u < 0 || v < 0 || u >= size.width || v >= size.height) continue;
			int d1 = INT32_MAX, d2 = INT32_MAX, bestFeature = -1;
			// The cells the window [u - r, u + r] x [v - r, v + r] overlaps, rows
			// first: no feature within r lies elsewhere.
			const int gx0 = std::max(0, int(std::floor((u - r) / m_cellSize)));
			const int gx1 = std::min(m_cols - 1, int((u + r) / m_cellSize));
			const int gy0 = std::max(0, int(std::floor((v - r) / m_cellSize)));
			const int gy1 = std::min(m_rows - 1, int((v + r) / m_cellSize));
			for (int gy = gy0; gy <= gy1; ++gy)
				for (int k = m_cellStart[std::size_t(gy * m_cols + gx0)];
					 k < m_cellStart[std::size_t(gy * m_cols + gx1 + 1)]; ++k)
				{
					const CellFeature& c = m_features[std::size_t(k)];
					if ((c.x - u) * (c.x - u) + (c.y - v) * (c.y - v) > r2) continue;
					const int d = kPopcount ? hammingByPopcount(c.descriptor, lm.descriptor.data())
											: hamming(c.descriptor, lm.descriptor.data());
					if (d < d1)
					{
						d2 = d1;
						d1 = d;
						bestFeature = c.index;
					}
					else if (d < d2)
						d2 = d;
				}
			if (bestFeature < 0 || d1 > o.max_hamming || (d2 != INT32_MAX && d1 > o.match_ratio * d2)) continue;
			auto& b = best[bestFeature];
			if (d1 < b.first || (d1 == b.first && id > b.second)) b = {d1, id};
		}
	}

   private:
	/** The pixel in double (the distance test's type) and the descriptor's
	 *  address at hand: the inner loop converted and looked them up at every
	 *  candidate. */
	struct CellFeature
	{
		double x, y;
		const std::uint8_t* descriptor;
		int index;
	};
	const FrameFeatures& m_frame;
	const TOdometryOptions& m_options;
	const double m_cellSize;
	const int m_cols, m_rows;
	std::vector<int> m_cellStart;
	std::vector<CellFeature> m_features;
};

#if defined(__x86_64__) && !defined(__POPCNT__)
/** The search with the popcount instruction, which x86-64's baseline lacks
 *  and every x86-64 processor since 2008 has: the descriptor count is the
 *  search's inner loop, and the instruction takes a tenth off the matching. The
 *  counts, so the matches, are the same. */
[[gnu::target("popcnt")]] void bestLandmarksByPopcountInstruction(const ProjectionSearch& search,
	const LandmarkMap& landmarks, const Eigen::Isometry3d& T_cw, std::vector<std::pair<int, int>>& best)
{
	search.bestLandmarks<true>(landmarks, T_cw, best);
}
#endif
}  // namespace

std::vector<Match> FeatureFrontend::matchByProjection(
	const FrameFeatures& frame, const LandmarkMap& landmarks, const Eigen::Isometry3d& T_cw) const
{
	const ProjectionSearch search(frame, m_options);
	std::vector<std::pair<int, int>> best(frame.keypoints.size(), {INT32_MAX, -1});
#if defined(__x86_64__) && !defined(__POPCNT__)
	if (__builtin_cpu_supports("popcnt"))
		bestLandmarksByPopcountInstruction(search, landmarks, T_cw, best);
	else
#endif
		search.bestLandmarks<false>(landmarks, T_cw, best);
	std::vector<Match> matches;
	for (int i = 0; i < int(best.size()); ++i)
		if (best[i].second >= 0) matches.push_back({i, best[i].second});
	return matches;
}

std::vector<Match> FeatureFrontend::matchByDescriptor(const FrameFeatures& frame, const LandmarkMap& landmarks) const
{
	// The two nearest landmarks of each feature, as OpenCV's brute-force k=2
	// matching finds them, with the SSE2 count of the projection search:
	// cv::BFMatcher paid a call of cv::hal::normHamming per pair, half the
	// time of measuring a loop.
	if (landmarks.size() < 2 || frame.descriptors.empty()) return {};
	std::vector<OrbDescriptor> train;
	std::vector<int> ids;
	train.reserve(landmarks.size());
	ids.reserve(landmarks.size());
	for (const auto& [id, lm] : landmarks)
	{
		train.push_back(lm.descriptor);
		ids.push_back(id);
	}
	// A tie for the nearest landmark fails the ratio test (match_ratio <= 1),
	// so the order of `train` does not change the matches.
	std::vector<Match> matches;
	for (int i = 0; i < frame.descriptors.rows; ++i)
	{
		const std::uint8_t* query = frame.descriptorData(i);
		int d1 = INT32_MAX, d2 = INT32_MAX, nearest = -1;
		for (std::size_t j = 0; j < train.size(); ++j)
		{
			const int d = hamming(query, train[j].data());
			if (d < d1)
			{
				d2 = d1;
				d1 = d;
				nearest = int(j);
			}
			else if (d < d2)
				d2 = d;
		}
		if (d1 <= m_options.max_hamming && d1 < m_options.match_ratio * d2) matches.push_back({i, ids[nearest]});
	}
	return matches;
}

std::optional<FeatureFrontend::PnpResult> FeatureFrontend::solvePnp(const FrameFeatures& frame,
	const LandmarkMap& landmarks, const std::vector<Match>& matches, const Eigen::Isometry3d& guess) const
{
	if (int(matches.size()) < m_options.min_inliers) return std::nullopt;
	std::vector<cv::Point3f> object;
	std::vector<cv::Point2f> image;
	for (const auto& m : matches)
	{
		const auto& p = landmarks.at(m.landmark).position;
		object.emplace_back(float(p.x()), float(p.y()), float(p.z()));
		image.push_back(frame.keypoints[m.feature].pt);
	}
	const cv::Matx33d K(frame.K.fx, 0, frame.K.cx, 0, frame.K.fy, frame.K.cy, 0, 0, 1);
	cv::Mat R, rvec, tvec;
	cv::eigen2cv(Eigen::Matrix3d(guess.rotation()), R);
	cv::Rodrigues(R, rvec);
	cv::eigen2cv(Eigen::Vector3d(guess.translation()), tvec);
	std::vector<int> inlierIdx;
	if (!cv::solvePnPRansac(object, image, K, cv::noArray(), rvec, tvec, /*useExtrinsicGuess=*/true,
			m_options.ransac_iterations, float(m_options.ransac_reprojection), 0.99, inlierIdx,
			cv::SOLVEPNP_ITERATIVE) ||
		int(inlierIdx.size()) < m_options.min_inliers)
		return std::nullopt;
	cv::Rodrigues(rvec, R);
	Eigen::Matrix3d Re;
	Eigen::Vector3d te;
	cv::cv2eigen(R, Re);
	cv::cv2eigen(tvec, te);
	PnpResult out{Eigen::Isometry3d::Identity(), {}};
	out.T_cw.linear() = Re;
	out.T_cw.translation() = te;
	for (int i : inlierIdx) out.inliers.push_back(matches[i]);
	// OpenCV's final iterative refinement on the consensus set can diverge
	// (seen on Bonn: 451 RANSAC inliers, none within the threshold at the
	// returned pose). The consensus set is sound, so the refinement that
	// follows starts from the guess instead.
	const auto consistent = std::count_if(out.inliers.begin(), out.inliers.end(),
		[&](const Match& m)
		{
			const cv::Point2f& px = frame.keypoints[m.feature].pt;
			return reprojectionError(out.T_cw, landmarks.at(m.landmark).position, Eigen::Vector2d(px.x, px.y),
					   frame.K) <= m_options.ransac_reprojection;
		});
	if (consistent < m_options.min_inliers) out.T_cw = guess;
	return out;
}
Observation observationOf(const FrameFeatures& f, int feature, int landmark)
{
	return {landmark, feature, Eigen::Vector2d(f.keypoints[feature].pt.x, f.keypoints[feature].pt.y),
		f.points[feature].z()};
}

std::vector<Observation> observationsOf(const FrameFeatures& f, const std::vector<Match>& matches)
{
	std::vector<Observation> out;
	out.reserve(matches.size());
	for (const auto& m : matches) out.push_back(observationOf(f, m.feature, m.landmark));
	return out;
}

std::vector<Match> inliersAt(const Eigen::Isometry3d& T, const FrameFeatures& f, const std::vector<Match>& matches,
	const LandmarkMap& landmarks, double maxError, double& squaredErrors)
{
	std::vector<Match> inliers;
	squaredErrors = 0;
	for (const auto& m : matches)
	{
		const double err = reprojectionError(T, landmarks.at(m.landmark).position,
			Eigen::Vector2d(f.keypoints[m.feature].pt.x, f.keypoints[m.feature].pt.y), f.K);
		if (err > maxError) continue;
		inliers.push_back(m);
		squaredErrors += err * err;
	}
	return inliers;
}

void addKeyframePoints(const Eigen::Isometry3d& T_cw, const cv::Mat& descriptors,
	const std::vector<Eigen::Vector3d>& points, int firstId, LandmarkMap& out)
{
	const Eigen::Isometry3d T_wc = T_cw.inverse();
	for (int i = 0; i < descriptors.rows; ++i)
		out[firstId + i] = Landmark{T_wc * points[std::size_t(i)], descriptorRow(descriptors, i)};
}
}  // namespace avm::odometry::detail
