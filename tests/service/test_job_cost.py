"""The fast path's cost estimate (service.routes.processes.job_cost), by hand."""

from __future__ import annotations

import math

import numpy as np

from algorithms.core.graphs import Graph
from algorithms.core.mesh import Mesh
from service.routes.processes import job_cost
from service.settings import Settings

BUDGET = Settings().fast_path_cost


def test_arrays_cost_their_numbers_times_the_square_of_the_dimension() -> None:
    four = np.zeros((4, 3))
    assert job_cost({"source": four, "target": four, "scale": True}) == 2 * 12 * 9
    # the dimension is the widest 2-D input's, a weight vector pays it too
    assert job_cost({"source": np.zeros((5, 2)), "weights": np.ones(5)}) == (10 + 5) * 4
    # a list of point sets: the sum of its arrays'
    assert job_cost({"shapes": [np.zeros((10, 2)), np.zeros((5, 2))]}) == 30 * 4


def test_a_graph_or_mesh_costs_its_numbers_times_the_root_of_its_size() -> None:
    edges = np.stack([np.arange(99), np.arange(1, 100)], axis=1)
    # 198 indices and the node count 100; size: 100 nodes
    assert job_cost({"graph": Graph(n_nodes=100, edges=edges)}) == 298 * 10
    mesh = Mesh(np.zeros((4, 3)), np.array([[0, 1, 2], [0, 2, 3]]))
    assert job_cost({"mesh": mesh}) == 18 * 2


def test_the_budget_keeps_the_closed_forms_and_sends_the_hostile_cases_away() -> None:
    thousand = np.zeros((1000, 3))
    assert job_cost({"source": thousand, "target": thousand}) <= BUDGET
    # #17.3: alignment.homography on 100 pairs in d = 40, 80 kB of JSON
    wide = np.zeros((100, 40))
    assert job_cost({"source": wide, "target": wide}) == 8000 * 1600 > BUDGET
    # a graph of 2M nodes and a single edge: 16 bytes of edges, but 2M unknowns
    lone = Graph(n_nodes=2_000_000, edges=np.array([[0, 1]]))
    assert job_cost({"graph": lone}) == (2_000_002) * math.sqrt(2_000_000) > BUDGET
