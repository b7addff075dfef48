#include "avm/detection/CocoClasses.h"

#include <algorithm>

namespace avm::detection
{
const std::vector<std::string>& cocoClassNames()
{
	static const std::vector<std::string> names = {"person", "bicycle", "car", "motorcycle", "airplane", "bus", "train",
		"truck", "boat", "traffic light", "fire hydrant", "stop sign", "parking meter", "bench", "bird", "cat", "dog",
		"horse", "sheep", "cow", "elephant", "bear", "zebra", "giraffe", "backpack", "umbrella", "handbag", "tie",
		"suitcase", "frisbee", "skis", "snowboard", "sports ball", "kite", "baseball bat", "baseball glove",
		"skateboard", "surfboard", "tennis racket", "bottle", "wine glass", "cup", "fork", "knife", "spoon", "bowl",
		"banana", "apple", "sandwich", "orange", "broccoli", "carrot", "hot dog", "pizza", "donut", "cake", "chair",
		"couch", "potted plant", "bed", "dining table", "toilet", "tv", "laptop", "mouse", "remote", "keyboard",
		"cell phone", "microwave", "oven", "toaster", "sink", "refrigerator", "book", "clock", "vase", "scissors",
		"teddy bear", "hair drier", "toothbrush"};
	return names;
}

std::optional<int> cocoClassId(const std::string& name)
{
	const auto& names = cocoClassNames();
	const auto it = std::find(names.begin(), names.end(), name);
	if (it == names.end()) return std::nullopt;
	return static_cast<int>(it - names.begin());
}

std::string cocoClassName(int id)
{
	const auto& names = cocoClassNames();
	if (id >= 0 && id < static_cast<int>(names.size())) return names[static_cast<std::size_t>(id)];
	return "class" + std::to_string(id);
}
}  // namespace avm::detection
