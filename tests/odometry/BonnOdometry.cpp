#include "BonnOdometry.h"

#include <map>

#include <mrpt/img/CImage.h>
#include <opencv2/imgproc.hpp>

#include "TestData.h"
#include "avm/detection/Detector.h"
#include "avm/evaluation/TrajectoryEvaluation.h"
#include "avm/io/RawlogFrameReader.h"

namespace avm::test
{
namespace
{
const std::map<std::size_t, std::vector<cv::Rect>>& bonnPersonBoxes()
{
	static const auto boxes = []
	{
		detection::TDetectorOptions opt;
		opt.model = sharedFile("models/yolox_nano.onnx").string();
		const auto detector = detection::createDetector(opt);
		std::map<std::size_t, std::vector<cv::Rect>> out;
		io::RawlogFrameReader reader(bonnRawlog());
		while (auto f = reader.next())
			for (const auto& d : detection::personsOnly(detector->detect(io::colourImage(*f->observation))))
				out[f->index].push_back(d.box);
		return out;
	}();
	return boxes;
}
}  // namespace

std::vector<cv::Rect> personBoxesOf(const io::RgbdFrame& f)
{
	const auto& boxes = bonnPersonBoxes();
	const auto it = boxes.find(f.index);
	return it == boxes.end() ? std::vector<cv::Rect>{} : it->second;
}

odometry::OdometryRun runBonn(bool maskPeople, odometry::TOdometryOptions opt)
{
	opt.mask_people = maskPeople;
	// Boxes are only for masking: an unmasked run does without the detector.
	return odometry::runOdometry(
		bonnRawlog(), opt, maskPeople ? odometry::PersonBoxSource(personBoxesOf) : odometry::PersonBoxSource());
}

odometry::TOdometryOptions driftingOdometry()
{
	odometry::TOdometryOptions o;
	o.keyframe_tracked_pose = false;
	o.motion_prior_sigma = 0;
	o.motion_gate = 0;
	o.refine_rounds = 1;
	o.window_size = 8;
	o.ba_max_landmarks = 250;
	o.person_box_margin = 10;
	return o;
}

std::vector<odometry::OdometryEstimate> runBonnSpoilt(std::size_t first, std::size_t last,
	const std::function<void(mrpt::obs::CObservation3DRangeScan&)>& spoil, io::Trajectory& trajectory,
	const odometry::TOdometryOptions& options, const AfterFrame& after)
{
	std::optional<odometry::VisualOdometry> vo;
	std::vector<odometry::OdometryEstimate> estimates;
	io::RawlogFrameReader reader(bonnRawlog());
	while (auto f = reader.next())
	{
		if (!vo) vo.emplace(options, f->groundTruth.value_or(mrpt::poses::CPose3D()));
		auto obs = *f->observation;
		const bool spoilt = f->index >= first && f->index <= last;
		if (spoilt) spoil(obs);
		estimates.push_back(vo->process(obs, spoilt ? std::vector<cv::Rect>{} : personBoxesOf(*f)));
		trajectory.push_back({f->timestamp(), estimates.back().pose});
		if (after) after(*vo, *f, estimates.back());
	}
	// The poses as the closed loops left them.
	const auto corrected = vo->trajectory();
	for (std::size_t i = 0; i < trajectory.size(); ++i) trajectory[i].pose = corrected[i];
	return estimates;
}

std::vector<io::RgbdFrame> bonnFrames(std::size_t first, std::size_t last)
{
	std::vector<io::RgbdFrame> frames;
	io::RawlogFrameReader reader(bonnRawlog());
	while (auto f = reader.next())
	{
		if (f->index > last) break;
		if (f->index >= first) frames.push_back(std::move(*f));
	}
	return frames;
}

ForwardBackward playForwardBackward(const odometry::TOdometryOptions& opt, const AfterFrame& after)
{
	std::optional<odometry::VisualOdometry> vo;
	std::optional<mrpt::poses::CPose3D> start;
	ForwardBackward out;
	std::vector<mrpt::poses::CPose3D> truth;
	const auto play = [&](const io::RgbdFrame& f)
	{
		if (!vo)
		{
			start = f.groundTruth;
			vo.emplace(opt, f.groundTruth.value_or(mrpt::poses::CPose3D()));
		}
		truth.push_back(f.groundTruth.value());
		const auto e = vo->process(*f.observation, personBoxesOf(f));
		if (after) after(*vo, f, e);
		out.loopsClosed += e.loopClosed;
		if (e.loop)
			out.loops.push_back(odometry::loopAccuracy(*e.loop, truth.at(e.loop->candidateFrame), truth.back()));
		++out.frames;
	};
	io::RawlogFrameReader reader(bonnRawlog());
	std::size_t last = 0;
	while (auto f = reader.next())
	{
		play(*f);
		last = f->index;
	}
	constexpr std::size_t chunk = 50;
	for (std::size_t end = last; end > 0;)
	{
		const std::size_t first = end >= chunk ? end - chunk : 0;
		const auto frames = bonnFrames(first, end - 1);
		for (auto it = frames.rbegin(); it != frames.rend(); ++it) play(*it);
		end = first;
	}
	const auto endPose = vo->trajectory().back();
	out.endError = (endPose.translation() - start->translation()).norm();
	return out;
}

void blurView(mrpt::obs::CObservation3DRangeScan& obs)
{
	cv::Mat blurred;
	cv::GaussianBlur(io::colourImage(obs), blurred, cv::Size(61, 61), 20.0);
	obs.intensityImage = mrpt::img::CImage(blurred, mrpt::img::DEEP_COPY);
}

void keepLeftOf(mrpt::obs::CObservation3DRangeScan& obs, int parts)
{
	obs.load();
	cv::Mat colour = io::colourImage(obs).clone();
	const int strip = colour.cols / parts;
	colour(cv::Rect(strip, 0, colour.cols - strip, colour.rows)).setTo(cv::Scalar(128, 128, 128));
	obs.intensityImage = mrpt::img::CImage(colour, mrpt::img::DEEP_COPY);
	if (obs.rangeImage_isExternallyStored()) obs.rangeImage_forceResetExternalStorage();
	obs.rangeImage.asEigen().rightCols(obs.rangeImage.cols() - strip).setZero();
}

io::Trajectory groundTruth()
{
	auto gt = bonnRawlog();
	gt.replace_filename("bonn_sub300_groundtruth.txt");
	return io::readTumTrajectory(gt);
}

double ate(const io::Trajectory& est, std::size_t from, std::size_t count)
{
	evaluation::TEvaluationOptions opt;
	opt.firstFrame = from;
	opt.maxFrames = count;
	return evaluation::evaluateTrajectory(est, groundTruth(), opt).ate.rmse;
}
}  // namespace avm::test
