"""The step of one world as a pipeline of compiled stages, and the runs that drive it.

``step_world`` is Box2D v3's soft step, for one world, top to bottom:

    body terms -> broadphase -> narrowphase -> wake touched islands (and again, until
    nothing more wakes) -> contact preparation with warm start -> colouring (a large
    world's manifolds) -> substeps [integrate
    velocities (gravity, forces, drag, rolling, springs) -> warm start -> solve ->
    integrate positions -> relax] -> restitution -> bodies deep in planes moved out ->
    store contacts, first contacts and damage -> clear forces -> sleep -> broken bodies
    -> sensors -> clock -> the envelope check (``refusal``)

``advance_world`` repeats it for one world, up to a number of steps or until the world
is at rest (a shot runs in one compiled call); ``advance`` does that for the worlds of a
plan, one after the other (the runner hands chunks of a batch to threads, each a call of
``advance``). Worlds never share anything during a step, so a world steps bitwise the
same alone, in a batch, and on any number of threads.

Only ``advance`` is compiled as a whole: ``advance_world`` and ``step_world`` are inlined
into it. numba links the stages a kernel calls into the kernel's own module and optimises
and emits machine code for all of it again, so each compiled level above the stages cost
about 2 s of every first run.

A step that finds more pairs or points than the scratch rows hold stops *before it
changes the world* (waking aside, which the retried step would do too) and asks for
room in its plan row; ``run`` grows the arrays and calls again, and the world carries
on exactly where it stood.

A step can also be refused: a spring too stiff for the substep (found before the world
changes) or a world that left the envelope (found at the end of the step). Each world's
first step in a call saves what steps write (``refusal.save_world``), so that the runner
can put every world back when any of them is refused: a refused call changes nothing.
"""

from __future__ import annotations

from . import context
from ._jit import JIT_DISABLED, borrowed, clear_stale_cache, inline, kernel
from .broadphase import find_pairs
from .colouring import colour_arrays, colour_step, unpack_step
from .contacts import carry_impulses, count_dormant, follow_bodies, prepare, store
from .events import break_bodies, record_contacts, sense
from .integrate import (
    apply_springs,
    integrate_positions,
    integrate_velocities,
    list_moving,
    refresh_rotation,
    spring_stability,
    step_terms,
)
from .joints import drop_joined_pairs, finish_joints, solve_joints, warm_start_joints
from .lanes import (
    follow_coloured,
    load_moving,
    load_states,
    solve_coloured,
    store_states,
    warm_start_coloured,
)
from .narrowphase import find_points
from .projection import project_out_of_planes
from .refusal import leaves_envelope, save_world
from .sleep import update_sleep, wake_touched
from .solver import relax, restitution, solve, warm_start
from .state import (
    AWAKE,
    CONTACT_COUNT,
    DYNAMIC,
    ENABLED,
    FX,
    FY,
    GROSS_IMPULSE,
    KEPT_TORQUE,
    KINEMATIC,
    OMEGA,
    PLANE,
    STEP_IMPULSE,
    STEPS,
    TORQUE,
    VX,
    VY,
)
from .workspace import MOVING, views

# A run's plan: one row per world it steps. BAD_SLOT is the refused spring or body,
# BAD_WHAT what took a body out of the envelope (refusal.SPEED, ...), SAVED 1 once the
# world's undo rows hold it as it was before the call.
PLAN_WORLD, PLAN_STEPS, PLAN_STATUS, NEED_PAIRS, NEED_POINTS = range(5)
BAD_SLOT, BAD_WHAT, SAVED = 5, 6, 7
PLAN_COLUMNS = 8
# Statuses; from UNSTABLE_SPRING on, the world was refused.
RUNNING, NEEDS_ROOM, UNSTABLE_SPRING, FAST_SPRING, LEFT_ENVELOPE = 0, 1, 2, 3, 4


@kernel
def split_layout(layout, bodies, springs):
    """The body shapes, spring ends and sensor kinds packed in ``Layout.rows``."""
    return layout[:bodies], layout[bodies : bodies + springs], layout[bodies + springs :]


@kernel
def at_rest(body_i, shapes, w) -> bool:
    """Nothing in world ``w`` moves: every enabled body asleep, fixed or a still kinematic."""
    for i in range(shapes.shape[0]):
        if body_i[w, i, ENABLED] == 1 and body_i[w, i, AWAKE] == 1 and shapes[i, 0] != PLANE:
            return False
    return True


@kernel
def rest_step(body, contact, world_i, time, w, ctx) -> None:
    """A step of a world at rest: only the clock moves (and nothing pushed)."""
    for j in range(world_i[w, CONTACT_COUNT]):
        contact[w, j, STEP_IMPULSE] = contact[w, j, GROSS_IMPULSE] = 0.0
        contact[w, j, KEPT_TORQUE] = 0.0
    body[w, :, FX] = 0.0
    body[w, :, FY] = 0.0
    body[w, :, TORQUE] = 0.0
    time[w] += ctx[context.DT]
    world_i[w, STEPS] += 1


@inline
def collide_and_wake(body, body_i, shapes, spring, ends, hull, w, ctx, scratch, plan_row) -> int:
    """Broadphase and narrowphase, waking the islands a moving body touches and looking
    again with them awake, until nothing more wakes. Returns the number of points, or -1
    when the scratch rows are too small (the plan row says how much is needed)."""
    terms, points, ids = scratch.terms, scratch.points, scratch.point_ids
    pairs, sorted_pairs, buckets = scratch.pairs, scratch.sorted_pairs, scratch.buckets
    sleeping = False  # nothing asleep (a rain with sleeping off): nothing to wake
    for i in range(shapes.shape[0]):
        dynamic_off = shapes[i, 1] == DYNAMIC and shapes[i, 0] != PLANE and terms[i, MOVING] == 0.0
        sleeping |= dynamic_off and body_i[w, i, ENABLED] == 1
    while True:
        n_pairs = find_pairs(body, body_i, shapes, w, ctx, terms, scratch.swept, pairs,
                             sorted_pairs, buckets)  # fmt: skip
        if n_pairs > pairs.shape[0]:
            plan_row[NEED_PAIRS] = n_pairs
            return -1
        if ends.shape[0]:
            n_pairs = drop_joined_pairs(body_i, spring, ends, w, pairs, n_pairs)
        n = find_points(body, hull, shapes, w, ctx, terms, pairs, n_pairs, points, ids)
        if n > points.shape[0]:
            plan_row[NEED_POINTS] = n
            return -1
        if not sleeping or not wake_touched(body, body_i, shapes, spring, ends, w, terms, ids, n):
            return n
        step_terms(body, body_i, shapes, spring, ends, hull, w, ctx, terms)


@inline
def colour(ctx, scratch, n) -> int:
    """A world of ``ctx[COLOUR_FROM]`` points or more: its two-point manifolds coloured
    and packed (``colouring.py``). Returns how many were (0: the world is in plain
    order)."""
    if n < ctx[context.COLOUR_FROM]:
        return 0
    return colour_step(scratch.terms, scratch.points, scratch.point_ids, n,
                       scratch.colour_floats, scratch.colour_ints,
                       ctx[context.RESTITUTION_THRESHOLD])  # fmt: skip


@inline
def substeps(body, body_i, spring, ends, w, ctx, scratch, n, coloured, n_moving) -> None:
    """Box2D v3's soft step: per substep integrate velocities, warm start, solve with the
    soft bias, integrate positions, relax without it (the joints before the contacts in
    each pass, ``joints.py``); then restitution once, and the joints' forces and breaks. A coloured
    world's ``coloured`` manifolds live in their own columns over the substeps, warm
    started, solved and their anchors moved there (``lanes.py``), their passes on the
    bodies' compact ``states`` (loaded before, stored after); the other points
    (``rest``) take ``warm_start``, ``follow_bodies`` and the sweeps, which a world whose
    points are all coloured does not call. The loops over bodies walk the ``n_moving``
    bodies that move only (``scratch.moving``, ``integrate.list_moving``)."""
    terms, points, ids = scratch.terms, scratch.points, scratch.point_ids
    floats, ints, states = scratch.colour_floats, scratch.colour_ints, scratch.states
    h = ctx[context.H]
    biased = (ctx[context.INV_H], ctx[context.PUSH_SPEED], True)
    unbiased = (ctx[context.INV_H], ctx[context.PUSH_SPEED], False)
    rest = n - 2 * coloured
    # the pairs the plain passes walk in a coloured world; none listed: all (``pair_at``)
    others = colour_arrays(floats, ints).others if coloured else ints[:0]
    count = int(ctx[context.SUBSTEPS])
    slots = scratch.moving
    if coloured:  # the rows of the bodies that do not move, for the whole step
        load_states(body, w, terms, states)
    links = ends.shape[0] > 0  # springs or joints
    for substep in range(count):
        integrate_velocities(body, w, terms, slots, n_moving)
        if links:
            apply_springs(body, body_i, spring, ends, w, terms, h)
            warm_start_joints(body, body_i, spring, ends, w, terms)
        if rest:
            warm_start(body, w, points, ids, n, others)
        if links:
            solve_joints(body, body_i, spring, ends, w, ctx, terms, True)
        if coloured:
            load_moving(body, w, terms, states, slots, n_moving)
            warm_start_coloured(states, floats, ints, coloured)
            solve_coloured(states, biased, floats, ints)
            store_states(body, w, states, slots, n_moving)
        solve(body, w, ctx, terms, points, ids, n, rest, others)
        integrate_positions(body, w, h, slots, n_moving)
        if links:
            solve_joints(body, body_i, spring, ends, w, ctx, terms, False)
        if rest:
            follow_bodies(body, w, ctx, terms, points, ids, n, others)
        if coloured:
            follow_coloured(body, w, floats, ints, coloured)
            load_moving(body, w, terms, states, slots, n_moving)
            solve_coloured(states, unbiased, floats, ints)
            store_states(body, w, states, slots, n_moving)
        relax(body, w, ctx, terms, points, ids, n, substep == count - 1, rest, others)
    if coloured:  # the coloured points' impulses, back where the rest read them
        unpack_step(points, floats, ints, coloured)
    restitution(body, w, ctx, terms, points, ids, n)
    if links:
        finish_joints(body, body_i, spring, ends, w, ctx)


@inline
def finish(state, shapes, ends, sensors, w, ctx, scratch, n, n_moving) -> None:
    """Everything after the solver: contacts, events, forces, sleep, the clock
    (``n_moving``: how many bodies ``scratch.moving`` lists)."""
    body, body_i, spring, sensor, contact, contact_i, world_i, time, _ = state
    terms, points, ids = scratch.terms, scratch.points, scratch.point_ids
    merged, merged_ids = scratch.merged, scratch.merged_ids
    store(body_i, contact, contact_i, world_i, w, terms, points, ids, n, merged, merged_ids)
    damaged = record_contacts(body, body_i, w, ctx, points, ids, n)
    refresh_rotation(body, shapes, w, scratch.moving, n_moving)
    for i in range(shapes.shape[0]):
        body[w, i, FX] = body[w, i, FY] = body[w, i, TORQUE] = 0.0
        if shapes[i, 1] == KINEMATIC and body_i[w, i, ENABLED] == 1:  # awake while it moves
            going = body[w, i, VX] != 0.0 or body[w, i, VY] != 0.0 or body[w, i, OMEGA] != 0.0
            body_i[w, i, AWAKE] = 1 if going else 0
    if ctx[context.SLEEPING] == 1.0:
        parents, members = scratch.parents, scratch.members
        update_sleep(body, body_i, spring, ends, w, ctx, terms, ids, n, parents, members,
                     scratch.moving, n_moving)  # fmt: skip
    if damaged:
        break_bodies(body, body_i, shapes, contact, contact_i, world_i, w)
    sense(body, body_i, shapes, sensor, sensors, contact, contact_i, world_i, w, terms,
          scratch.moving, n_moving)  # fmt: skip
    time[w] += ctx[context.DT]
    world_i[w, STEPS] += 1


@inline
def step_world(state, layout, ctx, w, scratch, plan_row) -> int:
    """One step of world ``w``; returns a status (``RUNNING`` when it stepped).

    ``state`` is the tuple ``(body, body_i, spring, sensor, contact, contact_i, world_i,
    time, hull)`` of ``WorldState``'s arrays."""
    body, body_i, spring, _, contact, contact_i, world_i, time, hull = state
    shapes, ends, sensors = split_layout(layout, body.shape[1], spring.shape[1])
    if at_rest(body_i, shapes, w):
        rest_step(body, contact, world_i, time, w, ctx)
        return RUNNING
    terms, points, ids = scratch.terms, scratch.points, scratch.point_ids
    step_terms(body, body_i, shapes, spring, ends, hull, w, ctx, terms)
    n = collide_and_wake(body, body_i, shapes, spring, ends, hull, w, ctx, scratch, plan_row)
    if n < 0:
        return NEEDS_ROOM
    needed = n + count_dormant(body_i, contact_i, world_i, w, terms)
    if needed > points.shape[0]:
        plan_row[NEED_POINTS] = needed
        return NEEDS_ROOM
    if ends.shape[0]:
        worst, _, too_fast = spring_stability(body, body_i, spring, ends, w, terms, ctx[context.H])
        if worst >= 0:
            plan_row[BAD_SLOT] = worst
            return FAST_SPRING if too_fast else UNSTABLE_SPRING
    carry_impulses(contact, contact_i, world_i, w, terms, points, ids, n)
    prepare(body, w, ctx, terms, points, ids, n)
    coloured = colour(ctx, scratch, n)
    n_moving = list_moving(terms, scratch.moving)
    substeps(body, body_i, spring, ends, w, ctx, scratch, n, coloured, n_moving)
    project_out_of_planes(body, hull, shapes, w, points, ids, n)
    finish(state, shapes, ends, sensors, w, ctx, scratch, n, n_moving)
    slot, what = leaves_envelope(body, body_i, shapes, w)
    if slot >= 0:
        plan_row[BAD_SLOT], plan_row[BAD_WHAT] = slot, what
        return LEFT_ENVELOPE
    return RUNNING


@inline
def advance_world(state, layout, ctx, plan, j, max_steps, until_rest, scratch, undo_floats,
                  undo_ints):  # fmt: skip
    """Step the world of plan row ``j`` until it has taken ``max_steps`` steps in this run
    (or, with ``until_rest``, is at rest), or a step cannot go on. ``scratch`` is its
    ``Scratch``; ``undo_floats``, ``undo_ints`` the runner's undo rows, which hold the
    world as it was before its first step in the call."""
    body, body_i = state[0], state[1]
    w = plan[j, PLAN_WORLD]
    shapes = layout[: body.shape[1]]
    if plan[j, SAVED] == 0:
        save_world(state, shapes, undo_floats, undo_ints, w)
        plan[j, SAVED] = 1
    while plan[j, PLAN_STEPS] < max_steps:
        if until_rest and at_rest(body_i, shapes, w):
            return
        status = step_world(state, layout, ctx, w, scratch, plan[j])
        if status != RUNNING:
            plan[j, PLAN_STATUS] = status
            return
        plan[j, PLAN_STEPS] += 1


@kernel
def advance(
    body, body_i, spring, sensor, contact, contact_i, world_i, time, hull, layout, ctx, plan,
    max_steps, until_rest, floats, ints, pairs, undo_floats, undo_ints, fresh,
) -> int:  # fmt: skip
    """``advance_world`` for every row of the plan, one after the other, with scratch row
    0 (``workspace.views``; ``pairs`` the capacity of its pair arrays); returns the largest status
    (``RUNNING``: every world went as far as asked). ``fresh``: the plan starts here, so
    its counters are zeroed first (the runner reuses its plan arrays; zeroing them here
    costs nothing next to a numpy call). Every stage gets the arrays ``borrowed`` (their
    reference counting cost small worlds nearly half their step, ``_jit``)."""
    body, body_i = borrowed(body), borrowed(body_i)
    spring, sensor = borrowed(spring), borrowed(sensor)
    contact, contact_i, world_i = borrowed(contact), borrowed(contact_i), borrowed(world_i)
    time, layout, ctx, plan = borrowed(time), borrowed(layout), borrowed(ctx), borrowed(plan)
    hull = borrowed(hull)
    floats, ints = borrowed(floats), borrowed(ints)
    undo_floats, undo_ints = borrowed(undo_floats), borrowed(undo_ints)
    state = (body, body_i, spring, sensor, contact, contact_i, world_i, time, hull)
    scratch = views(floats[0], ints[0], body.shape[1], contact.shape[1], pairs)
    worst = RUNNING
    for j in range(plan.shape[0]):
        if fresh:
            plan[j, PLAN_WORLD + 1 :] = 0
        if plan[j, PLAN_STATUS] == RUNNING:
            advance_world(
                state, layout, ctx, plan, j, max_steps, until_rest, scratch, undo_floats,
                undo_ints,
            )  # fmt: skip
        worst = max(worst, plan[j, PLAN_STATUS])
        if worst >= UNSTABLE_SPRING:  # the call is refused: the rest need not step
            return worst
    return worst


if not JIT_DISABLED:
    clear_stale_cache(advance.stats.cache_path)
