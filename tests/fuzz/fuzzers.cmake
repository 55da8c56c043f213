# One line per fuzz target: rescue_add_fuzzer(fuzz_NAME SOURCES fuzz_NAME.cpp DEPS libs...)
# The fuzz preset instruments every library for coverage (-fsanitize=fuzzer-no-link) and ASan/UBSan,
# so fuzzers link the decoders' libraries as the program does.
rescue_add_fuzzer(fuzz_nic_input SOURCES fuzz_nic_input.cpp DEPS rescue_app)
rescue_add_fuzzer(fuzz_sii_parser SOURCES fuzz_sii_parser.cpp DEPS rescue_ecat)
rescue_add_fuzzer(fuzz_sii_cache_file SOURCES fuzz_sii_cache_file.cpp DEPS rescue_ecat)
rescue_add_fuzzer(fuzz_coe_decoder SOURCES fuzz_coe_decoder.cpp DEPS rescue_ecat)
rescue_add_fuzzer(fuzz_coe_information SOURCES fuzz_coe_information.cpp DEPS rescue_ecat)
rescue_add_fuzzer(fuzz_error_joints_file SOURCES fuzz_error_joints_file.cpp DEPS rescue_core)
rescue_add_fuzzer(fuzz_frame_decoder SOURCES fuzz_frame_decoder.cpp DEPS rescue_ecat)
rescue_add_fuzzer(fuzz_redundant_merge SOURCES fuzz_redundant_merge.cpp DEPS rescue_ecat)
rescue_add_fuzzer(fuzz_capture_reader SOURCES fuzz_capture_reader.cpp DEPS rescue_ecat)
rescue_add_fuzzer(fuzz_captured_link SOURCES fuzz_captured_link.cpp DEPS rescue_ecat)
rescue_add_fuzz_seeds(make_ecat_fuzz_seeds SOURCES make_ecat_fuzz_seeds.cpp DEPS rescue_ecat)
rescue_add_fuzzer(fuzz_simulated_segment SOURCES fuzz_simulated_segment.cpp
  ${PROJECT_SOURCE_DIR}/drivers/sim/esc/esc.cpp ${PROJECT_SOURCE_DIR}/drivers/sim/esc/esc_al.cpp ${PROJECT_SOURCE_DIR}/drivers/sim/esc/esc_pdi.cpp
  ${PROJECT_SOURCE_DIR}/drivers/sim/esc/esc_logical.cpp ${PROJECT_SOURCE_DIR}/drivers/sim/esc/esc_memory.cpp ${PROJECT_SOURCE_DIR}/drivers/sim/esc/esc_clock.cpp
  ${PROJECT_SOURCE_DIR}/drivers/sim/esc/esc_dc.cpp ${PROJECT_SOURCE_DIR}/drivers/sim/esc/esc_sync_manager.cpp ${PROJECT_SOURCE_DIR}/drivers/sim/esc/esc_sii.cpp
  ${PROJECT_SOURCE_DIR}/drivers/sim/esc/esc_fmmu.cpp ${PROJECT_SOURCE_DIR}/drivers/sim/segment/simulated_segment.cpp ${PROJECT_SOURCE_DIR}/drivers/sim/segment/fault_command.cpp
  ${PROJECT_SOURCE_DIR}/drivers/sim/devices/minimal_sii.cpp ${PROJECT_SOURCE_DIR}/drivers/sim/devices/junction_device.cpp ${PROJECT_SOURCE_DIR}/drivers/sim/segment/robot_segment.cpp
  DEPS rescue_ecat rescue_hal rescue_core)
rescue_add_fuzzer(fuzz_master_replies SOURCES fuzz_master_replies.cpp DEPS rescue_drivers rescue_sim rescue_ecat)
rescue_add_fuzzer(fuzz_sdo_server SOURCES fuzz_sdo_server.cpp DEPS rescue_drivers rescue_sim rescue_ecat)
rescue_add_fuzzer(fuzz_protocol_decoder SOURCES fuzz_protocol_decoder.cpp DEPS rescue_app)
rescue_add_fuzzer(fuzz_config_file SOURCES fuzz_config_file.cpp DEPS rescue_app)
