/* Prints the layout of every dualform.h struct that the Python package
 * (sdk/python/dualform/_native.py) mirrors in ctypes, as the C compiler lays
 * it out: one line per struct, "struct PYTHON_NAME C_NAME SIZE ALIGNMENT", and
 * one per field, "field PYTHON_NAME FIELD OFFSET SIZE". test_struct_layout.py
 * compares the package's structs with it. A field renamed or removed from the
 * header fails this program's build; one added changes the struct's size. */
#include <stdalign.h>
#include <stddef.h>
#include <stdio.h>

#include "dualform/dualform.h"

#define STRUCT(py, c) printf("struct %s %s %zu %zu\n", #py, #c, sizeof(c), (size_t)alignof(c));
#define FIELD(py, c, f) \
    printf("field %s %s %zu %zu\n", #py, #f, offsetof(c, f), sizeof(((c*)0)->f));

int main(void) {
    STRUCT(Camera, dfm_camera)
    FIELD(Camera, dfm_camera, eye)
    FIELD(Camera, dfm_camera, target)
    FIELD(Camera, dfm_camera, up)
    FIELD(Camera, dfm_camera, fov_y_degrees)
    FIELD(Camera, dfm_camera, width)
    FIELD(Camera, dfm_camera, height)

    STRUCT(Vec3Input, dfm_vec3_input)
    FIELD(Vec3Input, dfm_vec3_input, data)
    FIELD(Vec3Input, dfm_vec3_input, count)
    FIELD(Vec3Input, dfm_vec3_input, stride)
    FIELD(Vec3Input, dfm_vec3_input, type)

    STRUCT(Vec3Output, dfm_vec3_output)
    FIELD(Vec3Output, dfm_vec3_output, data)
    FIELD(Vec3Output, dfm_vec3_output, count)
    FIELD(Vec3Output, dfm_vec3_output, stride)
    FIELD(Vec3Output, dfm_vec3_output, type)

    STRUCT(Allocator, dfm_allocator)
    FIELD(Allocator, dfm_allocator, alloc)
    FIELD(Allocator, dfm_allocator, free)
    FIELD(Allocator, dfm_allocator, user)

    STRUCT(JobSystem, dfm_job_system)
    FIELD(JobSystem, dfm_job_system, enqueue)
    FIELD(JobSystem, dfm_job_system, user)

    STRUCT(ContextDesc, dfm_context_desc)
    FIELD(ContextDesc, dfm_context_desc, struct_size)
    FIELD(ContextDesc, dfm_context_desc, header_version)
    FIELD(ContextDesc, dfm_context_desc, allocator)
    FIELD(ContextDesc, dfm_context_desc, log)
    FIELD(ContextDesc, dfm_context_desc, log_user)
    FIELD(ContextDesc, dfm_context_desc, worker_count)
    FIELD(ContextDesc, dfm_context_desc, pick_thread_count)
    FIELD(ContextDesc, dfm_context_desc, models_directory)
    FIELD(ContextDesc, dfm_context_desc, reference_folder)
    FIELD(ContextDesc, dfm_context_desc, work_mode)
    FIELD(ContextDesc, dfm_context_desc, job_system)

    STRUCT(MeshDesc, dfm_mesh_desc)
    FIELD(MeshDesc, dfm_mesh_desc, struct_size)
    FIELD(MeshDesc, dfm_mesh_desc, positions)
    FIELD(MeshDesc, dfm_mesh_desc, indices)
    FIELD(MeshDesc, dfm_mesh_desc, triangle_count)
    FIELD(MeshDesc, dfm_mesh_desc, index_stride)
    FIELD(MeshDesc, dfm_mesh_desc, weld)
    FIELD(MeshDesc, dfm_mesh_desc, weld_tolerance)

    STRUCT(MeshInfo, dfm_mesh_info)
    FIELD(MeshInfo, dfm_mesh_info, vertex_count)
    FIELD(MeshInfo, dfm_mesh_info, triangle_count)
    FIELD(MeshInfo, dfm_mesh_info, bounds_min)
    FIELD(MeshInfo, dfm_mesh_info, bounds_max)
    FIELD(MeshInfo, dfm_mesh_info, diagonal)
    FIELD(MeshInfo, dfm_mesh_info, components)
    FIELD(MeshInfo, dfm_mesh_info, boundary_edges)
    FIELD(MeshInfo, dfm_mesh_info, bake_count)
    FIELD(MeshInfo, dfm_mesh_info, redo_count)
    FIELD(MeshInfo, dfm_mesh_info, surface_vertex_count)

    STRUCT(MeshMemory, dfm_mesh_memory)
    FIELD(MeshMemory, dfm_mesh_memory, rest_pose)
    FIELD(MeshMemory, dfm_mesh_memory, adjacency)
    FIELD(MeshMemory, dfm_mesh_memory, model)
    FIELD(MeshMemory, dfm_mesh_memory, history)
    FIELD(MeshMemory, dfm_mesh_memory, pick_scene)
    FIELD(MeshMemory, dfm_mesh_memory, total)

    STRUCT(Hit, dfm_hit)
    FIELD(Hit, dfm_hit, hit)
    FIELD(Hit, dfm_hit, face)
    FIELD(Hit, dfm_hit, vertex)
    FIELD(Hit, dfm_hit, point)
    FIELD(Hit, dfm_hit, distance)
    FIELD(Hit, dfm_hit, barycentric)

    STRUCT(WaterFillDiagnosis, dfm_water_fill_diagnosis)
    FIELD(WaterFillDiagnosis, dfm_water_fill_diagnosis, loops)
    FIELD(WaterFillDiagnosis, dfm_water_fill_diagnosis, bounded_by_last_loop)
    FIELD(WaterFillDiagnosis, dfm_water_fill_diagnosis, suspect)

    STRUCT(SolverSettings, dfm_solver_settings)
    FIELD(SolverSettings, dfm_solver_settings, tolerance)
    FIELD(SolverSettings, dfm_solver_settings, max_iterations)
    FIELD(SolverSettings, dfm_solver_settings, handle_weight)
    FIELD(SolverSettings, dfm_solver_settings, hard_handles)
    FIELD(SolverSettings, dfm_solver_settings, method)
    FIELD(SolverSettings, dfm_solver_settings, preconditioner)
    FIELD(SolverSettings, dfm_solver_settings, disable_prediction)
    FIELD(SolverSettings, dfm_solver_settings, reserved)

    STRUCT(HandleGroup, dfm_handle_group)
    FIELD(HandleGroup, dfm_handle_group, vertices)
    FIELD(HandleGroup, dfm_handle_group, count)

    STRUCT(FrameInfo, dfm_frame_info)
    FIELD(FrameInfo, dfm_frame_info, generation)
    FIELD(FrameInfo, dfm_frame_info, status)
    FIELD(FrameInfo, dfm_frame_info, converged)
    FIELD(FrameInfo, dfm_frame_info, partial)
    FIELD(FrameInfo, dfm_frame_info, iterations)
    FIELD(FrameInfo, dfm_frame_info, last_update)
    FIELD(FrameInfo, dfm_frame_info, solve_ms)
    FIELD(FrameInfo, dfm_frame_info, checksum)
    FIELD(FrameInfo, dfm_frame_info, preparing)

    STRUCT(SessionDesc, dfm_session_desc)
    FIELD(SessionDesc, dfm_session_desc, struct_size)
    FIELD(SessionDesc, dfm_session_desc, roi)
    FIELD(SessionDesc, dfm_session_desc, groups)
    FIELD(SessionDesc, dfm_session_desc, group_count)
    FIELD(SessionDesc, dfm_session_desc, solver)
    FIELD(SessionDesc, dfm_session_desc, on_frame)
    FIELD(SessionDesc, dfm_session_desc, on_frame_user)

    STRUCT(VertexOutput, dfm_vertex_output)
    FIELD(VertexOutput, dfm_vertex_output, struct_size)
    FIELD(VertexOutput, dfm_vertex_output, data)
    FIELD(VertexOutput, dfm_vertex_output, count)
    FIELD(VertexOutput, dfm_vertex_output, stride)
    FIELD(VertexOutput, dfm_vertex_output, position_offset)
    FIELD(VertexOutput, dfm_vertex_output, normal_offset)
    FIELD(VertexOutput, dfm_vertex_output, write_positions)
    FIELD(VertexOutput, dfm_vertex_output, write_normals)
    FIELD(VertexOutput, dfm_vertex_output, changed_only)

    STRUCT(FrameView, dfm_frame_view)
    FIELD(FrameView, dfm_frame_view, roi_positions)
    FIELD(FrameView, dfm_frame_view, roi_positions_f64)
    FIELD(FrameView, dfm_frame_view, roi_vertices)
    FIELD(FrameView, dfm_frame_view, roi_count)
    FIELD(FrameView, dfm_frame_view, normals)
    FIELD(FrameView, dfm_frame_view, normal_vertices)
    FIELD(FrameView, dfm_frame_view, normal_count)

    STRUCT(SessionMemory, dfm_session_memory)
    FIELD(SessionMemory, dfm_session_memory, factor)
    FIELD(SessionMemory, dfm_session_memory, normal_matrix)
    FIELD(SessionMemory, dfm_session_memory, iteration)
    FIELD(SessionMemory, dfm_session_memory, frames)
    FIELD(SessionMemory, dfm_session_memory, staging)
    FIELD(SessionMemory, dfm_session_memory, total)

    STRUCT(Quality, dfm_quality)
    FIELD(Quality, dfm_quality, max_handle_error)
    FIELD(Quality, dfm_quality, mean_abs_log_edge)
    FIELD(Quality, dfm_quality, max_abs_log_edge)
    FIELD(Quality, dfm_quality, mean_normal_change_deg)
    FIELD(Quality, dfm_quality, max_fixed_move)
    FIELD(Quality, dfm_quality, dual_magnitude_error)
    FIELD(Quality, dfm_quality, flipped_faces)
    FIELD(Quality, dfm_quality, creased_edges)

    STRUCT(SolveReport, dfm_solve_report)
    FIELD(SolveReport, dfm_solve_report, unknowns)
    FIELD(SolveReport, dfm_solve_report, rows)
    FIELD(SolveReport, dfm_solve_report, normal_nonzeros)
    FIELD(SolveReport, dfm_solve_report, setup_ms)
    FIELD(SolveReport, dfm_solve_report, krylov_iterations)
    FIELD(SolveReport, dfm_solve_report, linear_residual)
    FIELD(SolveReport, dfm_solve_report, linear_converged)

    STRUCT(LoadReport, dfm_load_report)
    FIELD(LoadReport, dfm_load_report, polygons)
    FIELD(LoadReport, dfm_load_report, triangulated_polygons)
    FIELD(LoadReport, dfm_load_report, dropped_faces)

    STRUCT(MeshSummary, dfm_mesh_summary)
    FIELD(MeshSummary, dfm_mesh_summary, edges)
    FIELD(MeshSummary, dfm_mesh_summary, boundary_edges)
    FIELD(MeshSummary, dfm_mesh_summary, non_manifold_edges)
    FIELD(MeshSummary, dfm_mesh_summary, inconsistent_edges)
    FIELD(MeshSummary, dfm_mesh_summary, components)
    FIELD(MeshSummary, dfm_mesh_summary, isolated_vertices)
    FIELD(MeshSummary, dfm_mesh_summary, degenerate_triangles)
    FIELD(MeshSummary, dfm_mesh_summary, closed)

    STRUCT(SaveOptions, dfm_save_options)
    FIELD(SaveOptions, dfm_save_options, struct_size)
    FIELD(SaveOptions, dfm_save_options, ply_encoding)
    FIELD(SaveOptions, dfm_save_options, ply_float)
    FIELD(SaveOptions, dfm_save_options, obj_normals)
    FIELD(SaveOptions, dfm_save_options, morph_target_name)
    return 0;
}
