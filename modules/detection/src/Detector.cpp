#include "avm/detection/Detector.h"

#include <mrpt/io/vector_loadsave.h>
#include <opencv2/dnn.hpp>
#include <opencv2/objdetect.hpp>

#include <algorithm>
#include <mutex>
#include <sstream>
#include <stdexcept>

#include "avm/detection/CocoClasses.h"
#include "avm/detection/OutputDecoders.h"
#include "DnnGraph.h"

namespace avm::detection
{
namespace fs = std::filesystem;

DetectorBase::~DetectorBase() = default;

std::vector<Detection> personsOnly(const std::vector<Detection>& detections)
{
	std::vector<Detection> persons;
	std::copy_if(detections.begin(), detections.end(), std::back_inserter(persons),
		[](const Detection& d) { return d.className == "person"; });
	return persons;
}

namespace
{
std::string firstLine(const std::string& s)
{
	const auto nl = s.find('\n');
	return s.substr(0, std::min<std::size_t>(nl, 300));
}

std::string shapeString(const std::vector<int>& shape)
{
	std::string s;
	for (int d : shape) s += (s.empty() ? "" : "x") + std::to_string(d);
	return s;
}

std::vector<int> shapeOf(const cv::Mat& m) { return std::vector<int>(m.size.p, m.size.p + m.dims); }

/** A YOLO-family ONNX model run by cv::dnn on the CPU. */
class DnnDetector : public DetectorBase
{
   public:
	DnnDetector(const fs::path& modelFile, const TDetectorOptions& o)
		: m_file(modelFile), m_input(o.input_width, o.input_height), m_classNames(o.classes)
	{
		m_params.classIds = o.classIds();
		m_params.scoreThreshold = static_cast<float>(o.score_threshold);
		m_params.nmsThreshold = static_cast<float>(o.nms_threshold);
		if (!fs::exists(m_file))
			throw std::runtime_error(m_file.string() +
									 ": model file not found (run scripts/get-data.sh to fetch the default model, "
									 "or set [detection] model; model = \"\" uses the HOG people detector)");
		if (!fs::is_regular_file(m_file)) throw std::runtime_error(m_file.string() + ": model path is not a file");
		detail::DnnGraph graph;
		try
		{
			graph.onnx = mrpt::io::file_get_contents(m_file.string());
		}
		catch (const std::exception&)
		{
			throw std::runtime_error(m_file.string() + ": cannot read the model file");
		}
		if (o.simplify_graph) graph = detail::rewriteForDnn(std::move(graph.onnx));
		m_inputSpaceToDepth = graph.inputSpaceToDepth;
		m_outputTransposed = graph.outputTransposed;
		m_graphSummary = graph.summary();
		try
		{
			m_net = cv::dnn::readNetFromONNX(graph.onnx.data(), graph.onnx.size());
		}
		catch (const cv::Exception& e)
		{
			throw std::runtime_error(m_file.string() + ": cannot load as an ONNX model (" + firstLine(e.what()) + ")");
		}
		if (m_net.empty()) throw std::runtime_error(m_file.string() + ": cannot load as an ONNX model (empty network)");
		m_net.setPreferableBackend(cv::dnn::DNN_BACKEND_OPENCV);
		m_net.setPreferableTarget(cv::dnn::DNN_TARGET_CPU);
		resolveLayout(o.layout);
	}

	std::vector<Detection> detect(const cv::Mat& bgr) override
	{
		Letterbox lb;
		const cv::Mat blob = makeInputBlob(bgr, m_layout, m_input, lb);
		std::lock_guard<std::mutex> lock(m_netMutex);
		return decodeOutput(m_layout, run(blob), lb, m_params);
	}

	std::string description() const override
	{
		std::ostringstream s;
		s << "ONNX " << toString(m_layout) << " model " << m_file.string() << " (cv::dnn, input " << m_input.width
		  << "x" << m_input.height << ", classes: " << m_classNames << ", score >= " << m_params.scoreThreshold
		  << ", NMS IoU " << m_params.nmsThreshold << (m_graphSummary.empty() ? "" : ", " + m_graphSummary) << ")";
		return s.str();
	}

   private:
	/** The network on an input blob, its output as the model as exported gives it. */
	cv::Mat run(const cv::Mat& blob)
	{
		m_net.setInput(m_inputSpaceToDepth ? m_inputSpaceToDepth->apply(blob) : blob);
		const cv::Mat out = m_net.forward();
		return m_outputTransposed ? detail::swapLastAxes(out) : out;
	}

	/** Runs the network once on a grey input: the output shape tells the
	 *  layout, and a model that loads but cannot run fails here, at start-up. */
	void resolveLayout(OutputLayout wanted)
	{
		const OutputLayout probeLayout = wanted == OutputLayout::Auto ? OutputLayout::Yolox : wanted;
		Letterbox lb;
		const cv::Mat probe(m_input, CV_8UC3, cv::Scalar::all(114));
		cv::Mat out;
		try
		{
			out = run(makeInputBlob(probe, probeLayout, m_input, lb));
		}
		catch (const cv::Exception& e)
		{
			throw std::runtime_error(m_file.string() + ": the model does not run on a " +
									 std::to_string(m_input.width) + "x" + std::to_string(m_input.height) +
									 " input (check [detection] input_width/input_height): " + firstLine(e.what()));
		}
		const auto recognised = recogniseLayout(shapeOf(out), m_input);
		if (wanted == OutputLayout::Auto)
		{
			if (!recognised)
				throw std::runtime_error(
					m_file.string() + ": output shape " + shapeString(shapeOf(out)) + " is not a known layout for a " +
					std::to_string(m_input.width) + "x" + std::to_string(m_input.height) + " input (expected " +
					expectedShape(OutputLayout::Auto, m_input) + "); set [detection] layout and the input size");
			m_layout = *recognised;
		}
		else
		{
			if (recognised != wanted)
				throw std::runtime_error(m_file.string() + ": output shape " + shapeString(shapeOf(out)) +
										 " does not fit [detection] layout = " + toString(wanted) + " (expected " +
										 expectedShape(wanted, m_input) + ")");
			m_layout = wanted;
		}
	}

	fs::path m_file;
	cv::Size m_input;
	std::string m_classNames;
	DecodeParams m_params;
	OutputLayout m_layout = OutputLayout::Yolox;
	std::optional<detail::SpaceToDepth> m_inputSpaceToDepth;
	bool m_outputTransposed = false;
	std::string m_graphSummary;
	cv::dnn::Net m_net;
	std::mutex m_netMutex;
};

/** OpenCV's HOG + linear SVM pedestrian detector (Dalal-Triggs, 64x128
 *  window): no weights to fetch, upright people of at least ~64x128 px. */
class HogPeopleDetector : public DetectorBase
{
   public:
	explicit HogPeopleDetector(const TDetectorOptions& o) : m_hitThreshold(o.hog_hit_threshold)
	{
		const auto ids = o.classIds();
		if (std::find(ids.begin(), ids.end(), 0) == ids.end())
			throw std::invalid_argument(
				"[detection] classes = " + o.classes +
				": the HOG people detector (model = \"\") only finds persons; set a model for other classes");
		m_hog.setSVMDetector(cv::HOGDescriptor::getDefaultPeopleDetector());
	}

	std::vector<Detection> detect(const cv::Mat& bgr) override
	{
		if (bgr.empty() || bgr.type() != CV_8UC3)
			throw std::invalid_argument("detector input must be a non-empty BGR CV_8UC3 image");
		std::vector<cv::Rect> found;
		std::vector<double> weights;
		m_hog.detectMultiScale(bgr, found, weights, m_hitThreshold, cv::Size(8, 8), cv::Size(), 1.05, 2.0);
		std::vector<Detection> out;
		const cv::Rect frame(0, 0, bgr.cols, bgr.rows);
		for (std::size_t i = 0; i < found.size(); ++i)
		{
			const cv::Rect box = found[i] & frame;
			if (box.empty()) continue;
			out.push_back({cv::Rect2f(box), 0, "person", i < weights.size() ? static_cast<float>(weights[i]) : 0.f});
		}
		std::stable_sort(
			out.begin(), out.end(), [](const Detection& a, const Detection& b) { return a.score > b.score; });
		return out;
	}

	std::string description() const override
	{
		std::ostringstream s;
		s << "HOG people detector (OpenCV default linear SVM, no model file; hit threshold " << m_hitThreshold << ")";
		return s.str();
	}

   private:
	double m_hitThreshold;
	cv::HOGDescriptor m_hog;  // detectMultiScale is const: safe to share across calls
};
}  // namespace

std::unique_ptr<DetectorBase> createDetector(const TDetectorOptions& options, const fs::path& root)
{
	options.validate();
	if (options.model.empty()) return std::make_unique<HogPeopleDetector>(options);
	return std::make_unique<DnnDetector>(resolveModelPath(options.model, root), options);
}
}  // namespace avm::detection
