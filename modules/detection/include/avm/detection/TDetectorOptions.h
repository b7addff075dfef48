// Options of the person detector, section [detection] of an avm .ini
// (ini/default.ini documents every key).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "avm/io/IniKeyOptions.h"

namespace avm::detection
{
/** How a model's output tensor is laid out (see OutputDecoders.h). */
enum class OutputLayout
{
	Auto,    //!< recognised from the output shape and input size
	Yolox,   //!< 1xNx85, raw grid outputs (Megvii YOLOX export)
	Yolov5,  //!< 1xNx85, decoded boxes with objectness (YOLOv5/v7)
	Yolov8   //!< 1x84xN, decoded boxes, no objectness (YOLOv8/YOLO11)
};
/** "auto", "yolox", "yolov5", "yolov8". */
std::string toString(OutputLayout layout);
/** Throws std::invalid_argument listing the accepted names. */
OutputLayout parseOutputLayout(const std::string& name);

struct TDetectorOptions : public io::CIniKeyOptions<TDetectorOptions>
{
	/** ONNX model file as the ini gives it ("" = OpenCV's HOG people detector,
	 *  no weights). A relative path is resolved by resolveModelPath(). */
	std::string model = "datasets/models/yolox_nano.onnx";
	OutputLayout layout = OutputLayout::Auto;
	/** COCO class names to keep, comma separated (e.g. "person, dog"). */
	std::string classes = "person";
	double score_threshold = 0.3;  //!< keep detections scoring at least this (0..1)
	double nms_threshold = 0.45;   //!< IoU above which the weaker box of a class is dropped
	/** [px] Network input. 256x192, not YOLOX-Nano's 416x416, for real time
	 *  on 2 cores: the 640x480 frame is letterboxed to it exactly, and the
	 *  persons within the depth range (the only ones a region or the odometry
	 *  uses) are large enough at it. YOLOv5/v8 are usually trained at 640. */
	int input_width = 256;
	int input_height = 192;  //!< [px]
	/** OpenCV worker threads (cv::setNumThreads, process-wide, set by the
	 *  application, not the detector); 0 = OpenCV's default. 1 gives the
	 *  detector thread and avm-map's odometry and map loop a core each on
	 *  2 cores. */
	int threads = 1;
	double hog_hit_threshold = 0.0;  //!< HOG only: SVM margin a window needs to count
	/** The model's input space-to-depth (YOLOX and YOLOv5's Focus) done on
	 *  the blob before the network, and SiLU's Sigmoid-Mul pairs as Swish
	 *  layers that OpenCV fuses into the convolutions: the same network in a
	 *  form cv::dnn 4.6 runs faster (src/DnnGraph.h). */
	bool simplify_graph = true;

	/** Every key: name, member, unit, description, check. */
	static io::IniKeys<TDetectorOptions> iniKeys();
	void loadFromConfigFile(const mrpt::config::CConfigFileBase& source, const std::string& section) override;
	/** Throws std::invalid_argument naming "[section] key" and the bad value. */
	void validate(const std::string& section = "detection") const;

	/** COCO ids of `classes`; throws std::invalid_argument naming
	 *  "[section] classes" and the unknown name. */
	std::vector<int> classIds(const std::string& section = "detection") const;
};

/** The model file to open: `model` if absolute, else `root / model`. The
 *  application passes the project root; "" stays "" (HOG). */
std::filesystem::path resolveModelPath(const std::string& model, const std::filesystem::path& root);
}  // namespace avm::detection
