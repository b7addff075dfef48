// A 2-D object detection and the interface every detector implements.
#pragma once

#include <opencv2/core/types.hpp>

#include <string>
#include <vector>

namespace cv
{
class Mat;
}

namespace avm::detection
{
struct Detection
{
	cv::Rect2f box;         //!< [px] in the input image, clipped to it
	int classId = -1;       //!< COCO id (0 = person)
	std::string className;  //!< COCO name ("person")
	float score = 0;        //!< model confidence 0..1 (HOG: SVM margin, see HogPeopleDetector)
};

/** Thread safety: instances share no mutable state, so different instances
 *  may run on different threads at the same time. Calls to detect() on one
 *  instance are serialised internally (the network is not re-entrant). */
class DetectorBase
{
   public:
	virtual ~DetectorBase();
	/** Detections in a BGR CV_8UC3 image, after class filter, score threshold
	 *  and non-maximum suppression, best score first. */
	virtual std::vector<Detection> detect(const cv::Mat& bgr) = 0;
	/** Which detector runs, with its model file and settings, one line. */
	virtual std::string description() const = 0;
};

/** The persons among detections (className "person"). */
std::vector<Detection> personsOnly(const std::vector<Detection>& detections);
}  // namespace avm::detection
