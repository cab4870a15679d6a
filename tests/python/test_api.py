"""The public C++ API is all there, in snake_case (docs/python.md lists the
rules): a name missing from mochi fails here."""
import mochi

EXPECTED = {
    mochi.Scene: "create destroy is_alive create_rigid_actor create_deformable_actor create_rod_actor "
                 "create_articulated_actor get_actor destroy_actor for_each_actor get_num_actors "
                 "create_rigid_spherical_joint_constraint create_rigid_prismatic_joint_constraint "
                 "create_joint_rotation_range_constraint create_joint_rotation_tracking_constraint "
                 "create_rigid_pivot_position_constraint create_rigid_pivot_to_rigid_target_constraint "
                 "create_rigid_pivot_rotation_constraint create_deformable_node_position_constraint "
                 "create_deformable_node_to_deformable_node_constraint create_deformable_node_to_rigid_constraint "
                 "create_rod_element_rotation_to_rigid_constraint create_articulated_single_dof_target_constraint "
                 "create_articulated_single_dof_range_constraint create_articulated_3d_rotation_target_constraint "
                 "create_articulated_3d_rotation_range_constraint get_constraint for_each_constraint "
                 "destroy_constraint get_num_constraints step set_substep_params set_linear_solver get_time "
                 "get_params get_stats get_num_dofs register_query",
    mochi.Constraint: "get_handle get_type get_num_actors get_actor get_dof_indices_for_actor get_dimension "
                      "get_num_dofs is_range get_stiffness get_damping get_saturation set_stiffness set_damping "
                      "set_saturation set_target_position set_target_rotation set_target_transform "
                      "set_target_dof update_old_target get_deviation is_query_supported register_query "
                      "get_force get_limit_min_values get_limit_max_values has_curvature "
                      "get_hessian_approximation set_hessian_approximation get_effective_stiffness "
                      "get_effective_damping is_near_rigid_capped",
    mochi.Actor: "get_handle get_type get_num_dofs get_dof_offset",
    mochi.NodalActor: "get_num_nodes get_node_position get_node_velocity get_node_mass get_transform_rotation "
                      "get_node_dof_stride get_node_position_dofs get_node_positions",
    mochi.RigidActor: "get_mass get_inertia get_position get_rotation get_linear_velocity get_angular_velocity "
                      "set_pose set_velocity transform_point get_angular_momentum get_kinetic_energy",
    mochi.DeformableActor: "get_num_tetrahedra get_num_triangles get_num_hinges get_tetrahedra get_triangles "
                           "get_node_reference_position get_node_displacement get_total_mass "
                           "get_node_positions get_transform_position get_kinetic_energy get_elastic_energy "
                           "count_inverted_tetrahedra",
    mochi.RodActor: "get_num_elements get_node_reference_position get_node_positions get_twist "
                    "get_twist_velocity get_twist_inertia get_total_mass get_rest_length get_material_frame "
                    "get_material_frame_jacobian get_strain get_rest_strain get_stiffness get_kinetic_energy "
                    "get_elastic_energy",
    mochi.ArticulatedActor: "get_num_links get_block_solve is_solved_on_tree get_num_coupled_constraints get_num_coupled_dofs "
                            "get_num_modified_tree_factorizations get_num_gauss_newton_tree_factorizations get_joint_type get_parent get_joint_dof_offset get_joint_num_dofs "
                            "is_floating_base get_link_position get_link_rotation get_link_center_of_mass "
                            "get_link_linear_velocity get_link_angular_velocity get_link_mass "
                            "get_joint_positions get_joint_velocities get_joint_rotation get_joint_coordinate "
                            "get_kinetic_energy get_linear_momentum get_angular_momentum compute_mass_matrix "
                            "compute_bias_forces",
    mochi.RigidSphericalJointConstraint: "get_local_pos_a get_local_pos_b",
    mochi.RigidPrismaticJointConstraint: "get_offset get_lower_limit get_upper_limit",
    mochi.JointRotationRangeConstraint: "get_relative_rotation",
    mochi.JointRotationTrackingConstraint: "get_target_rotation",
    mochi.RigidPivotPositionConstraint: "get_local_pos get_target_position",
    mochi.RigidPivotToRigidTargetConstraint: "get_local_pos",
    mochi.RigidPivotRotationConstraint: "get_local_rotation",
    mochi.DeformableNodePositionConstraint: "get_node_index",
    mochi.DeformableNodeToRigidConstraint: "get_local_pos",
    mochi.RodElementRotationToRigidConstraint: "get_element_index get_target_rotation",
    mochi.ArticulatedSingleDofConstraint: "get_coordinate",
    mochi.Articulated3dRotationConstraint: "get_joint_rotation_vector",
    mochi.LinearSolver: "analyze factorize solve is_analyzed get_analyzed_pattern_version get_type is_iterative "
                        "set_relative_tolerance wants_near_null_space set_near_null_space get_num_object_builds "
                        "get_description get_factor_nonzeros get_factor_flops",
    mochi.VtkSeries: "add_frame get_path get_num_frames",
    mochi.Communicator: "world from_fortran_handle is_set get_fortran_handle get_size get_rank",
}

MODULE = ("Error ErrorCode ActorHandle ConstraintHandle hat exp exp_matrix log left_jacobian "
          "left_jacobian_inverse right_jacobian right_jacobian_inverse get_blas_info BlasInfo "
          "IntegratorType LinearSolverType PcgPreconditioner PcgParams validate_pcg_params "
          "available_pcg_preconditioners available_linear_solvers resolve_linear_solver_type "
          "DENSE_SOLVER_MAX_SIZE LinearSolveStatus LinearSolveResult SparseSymmetricMatrix create_linear_solver "
          "OrderingMethod HessianProjection NewtonParams SubstepParams SceneParams SceneStats Communicator ActorType "
          "JointType ArticulatedBlockSolve "
          "joint_dofs "
          "TetMaterialModel MembraneModel RigidActorParams DeformableActorParams RodActorParams ArticulatedLinkParams "
          "ArticulatedActorParams RodStiffness TetMesh TriangleMesh make_tet_box make_triangle_grid make_hinges "
          "read_tet_gen read_gmsh_tets read_gmsh_triangles read_obj validate_tet_mesh validate_triangle_mesh "
          "remove_unused_nodes signed_volume VtkPointData write_vtu write_vtu_polylines write_rods_vtu "
          "ConstraintType QueryType ConstraintHessian "
          "RigidSphericalJointConstraintParams RigidPrismaticJointConstraintParams "
          "JointRotationRangeConstraintParams JointRotationTrackingConstraintParams "
          "RigidPivotPositionConstraintParams RigidPivotToRigidTargetConstraintParams "
          "RigidPivotRotationConstraintParams DeformableNodePositionConstraintParams "
          "DeformableNodeToDeformableNodeConstraintParams DeformableNodeToRigidConstraintParams "
          "RodElementRotationToRigidConstraintParams ArticulatedSingleDofTargetConstraintParams "
          "ArticulatedSingleDofRangeConstraintParams Articulated3dRotationTargetConstraintParams "
          "Articulated3dRotationRangeConstraintParams DeformableNodeToDeformableNodeConstraint")


def test_every_public_name_is_bound():
    missing = [name for name in MODULE.split() if not hasattr(mochi, name)]
    for cls, names in EXPECTED.items():
        missing += [f"{cls.__name__}.{name}" for name in names.split() if not hasattr(cls, name)]
    assert not missing


def test_every_enum_value_is_bound():
    # the C++ enums, value for value (None is a Python keyword: None_)
    assert len(mochi.ConstraintType.__members__) == 15
    assert list(mochi.ErrorCode.__members__) == [
        "None_", "InvalidArgument", "InvalidHandle", "NotSupported", "InvalidState", "NewtonFailed",
        "LinearSolverFailed", "NonFiniteState", "BackendError"]
    assert list(mochi.JointType.__members__) == ["Fixed", "Revolute", "Prismatic", "Spherical", "Free"]
    assert list(mochi.ArticulatedBlockSolve.__members__) == ["Tree", "Dense"]
    assert list(mochi.ActorType.__members__) == ["Rigid", "Deformable", "Rod", "Articulated"]
    assert list(mochi.IntegratorType.__members__) == ["BackwardEuler", "Bdf2"]
    assert list(mochi.LinearSolverType.__members__) == ["Auto", "Cholmod", "PetscPcg", "Dense", "PetscMumps"]
    assert len(mochi.PcgPreconditioner.__members__) == 7
    assert list(mochi.ConstraintHessian.__members__) == [
        "SceneDefault", "GaussNewton", "GeometricStiffness", "GeometricStiffnessDiagonal"]
    assert mochi.NewtonParams().constraint_hessian == mochi.ConstraintHessian.GeometricStiffness
    assert hasattr(mochi.SceneStats, "round_off_convergences")
    assert hasattr(mochi.SceneStats, "line_search_expansions")
    assert hasattr(mochi.SceneStats, "limited_steps")
    assert hasattr(mochi.SceneStats, "second_order_corrections")
    assert hasattr(mochi.SceneStats, "diagonal_shifts")
    assert hasattr(mochi.SceneStats, "truncated_solves")
    assert mochi.PcgParams().truncated_steps is True
    assert mochi.PcgParams(truncated_steps=False).truncated_steps is False
    assert mochi.NewtonParams().near_rigid_beta == 0
    assert hasattr(mochi.SceneStats, "near_rigid_constraints")


def test_everything_has_a_docstring():
    undocumented = []
    for cls in EXPECTED:
        if not (cls.__doc__ or "").strip():
            undocumented.append(cls.__name__)
    for name in ["make_tet_box", "exp", "create_linear_solver", "write_vtu"]:
        if not (getattr(mochi, name).__doc__ or "").strip():
            undocumented.append(name)
    assert not undocumented
    # fields carry the C++ field documentation
    assert "pivot r_A in A's body frame" in mochi.RigidSphericalJointConstraintParams.local_pos_a.__doc__
