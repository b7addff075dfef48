# Fuzz targets over the map plugin and the detector (included by CMakeLists.txt).
avm_add_fuzz_target(map_ini DEPS avm-adaptive-octomap mrpt::maps)
avm_add_fuzz_target(map_deserialization DEPS avm-adaptive-octomap mrpt::maps)
avm_add_fuzz_target(detector_decoders DEPS avm-detection)
avm_add_fuzz_target(dnn_graph DEPS avm-detection)
# DnnGraph.h is the detection module's internal header.
target_include_directories(replay-dnn_graph PRIVATE ${CMAKE_SOURCE_DIR}/modules/detection/src)
if(AVM_FUZZ)
  target_include_directories(fuzz-dnn_graph PRIVATE ${CMAKE_SOURCE_DIR}/modules/detection/src)
endif()
