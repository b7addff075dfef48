# Fuzz targets over the map plugin and the detector (included by CMakeLists.txt).
avm_add_fuzz_target(map_ini DEPS avm-adaptive-octomap mrpt::maps)
avm_add_fuzz_target(map_deserialization DEPS avm-adaptive-octomap mrpt::maps)
avm_add_fuzz_target(detector_decoders DEPS avm-detection)
