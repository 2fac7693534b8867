"""simulate_many: the shots of simulate, one by one, in order, from worker processes."""

import pickle

import pytest

from physics import SceneError, batch, parse_scene, simulate, simulate_many
from physics.batch import CHUNK
from physics.examples import BREAKS, single_shot


def breaks(n):
    makes = list(BREAKS.values())
    return [makes[k % len(makes)](speed=2.0 + 0.5 * k) for k in range(n)]


@pytest.mark.parametrize("workers", [1, 2, None])
def test_same_shots_in_the_same_order(workers):
    scenes = breaks(7)
    many = simulate_many(scenes, workers=workers)
    assert [s.to_msgpack() for s in many] == [simulate(s).to_msgpack() for s in scenes]


def test_shots_read_in_any_order():
    """A batch from the workers is built shot by shot as read: any index, slices, from the end."""
    scenes = breaks(9)
    alone = [simulate(s).to_msgpack() for s in scenes]
    many = simulate_many(scenes, workers=2)
    assert len(many) == 9 and len(simulate_many(scenes, workers=1)) == 9
    assert many[-1].to_msgpack() == alone[-1] and many[4].to_msgpack() == alone[4]
    assert [s.to_msgpack() for s in many[1:8:3]] == alone[1:8:3]
    assert many[4] is many[4]  # built once
    with pytest.raises(IndexError):
        many[9]


def test_a_bad_scene_raises_as_it_would_alone():
    scenes = [*breaks(3), {"balls": {}}]
    with pytest.raises(SceneError):
        simulate_many(scenes, workers=2)


def test_workers_at_least_one():
    with pytest.raises(ValueError, match="at least 1"):
        simulate_many(breaks(2), workers=0)


def test_empty_batch():
    assert list(simulate_many([], workers=2)) == []


def test_a_shot_pickles_to_an_equal_shot():
    """simulate_many's results come back through pickle (Shot.__reduce__): all of it intact."""
    for scene in breaks(3):
        shot = simulate(scene)
        back = pickle.loads(pickle.dumps(shot))
        assert back == shot and back.to_msgpack() == shot.to_msgpack()
        for a, b in zip(back.events, shot.events, strict=True):
            assert a.model_fields_set == b.model_fields_set


def test_a_scene_pickles_to_an_equal_scene():
    scene = parse_scene(breaks(1)[0])
    back = pickle.loads(pickle.dumps(scene))
    assert back == scene and back.geometry is scene.geometry  # built once per process


def test_without_trajectories_the_events_and_finals_are_the_same():
    scenes = breaks(5)
    many = simulate_many(scenes, workers=2, trajectories=False)
    alone = simulate_many(scenes, workers=1, trajectories=False)
    for a, b, scene in zip(many, alone, scenes, strict=True):
        full = simulate(scene)
        assert a.trajectories == {} and b.trajectories == {}
        assert a == b == full.model_copy(update={"trajectories": {}})


def test_many_chunks_and_scene_documents_mixed_in():
    """More scenes than one chunk holds, parsed ones and documents alternating (and tables
    and models that differ): each comes back as alone, in order."""
    documents = [
        single_shot(0.5 + 0.02 * k, 2.5 * k) | ({"models": {"cushion": "han"}} if k % 3 else {})
        for k in range(2 * CHUNK + 5)
    ]
    documents[7] = BREAKS["snooker_break_off"](speed=3.0)
    scenes = [parse_scene(d) if k % 2 else d for k, d in enumerate(documents)]
    many = simulate_many(scenes, workers=2)
    assert [s.to_msgpack() for s in many] == [simulate(d).to_msgpack() for d in documents]


def test_packed_scenes_unpack_equal():
    scenes = [parse_scene(s) for s in breaks(4)]
    scenes.append(parse_scene(single_shot() | {"initial": {"1": {"v": [0.5, 0.1]}}}))
    assert batch._unpack(batch._pack(scenes)) == scenes
