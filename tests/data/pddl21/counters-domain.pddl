; Counters that must be put in increasing order (IPC 2023 numeric "counters", simplified).
(define (domain counters)
  (:requirements :typing :numeric-fluents)
  (:types counter)
  (:functions (value ?c - counter) (max-int))
  (:action increment
    :parameters (?c - counter)
    :precondition (<= (+ (value ?c) 1) (max-int))
    :effect (increase (value ?c) 1))
  (:action decrement
    :parameters (?c - counter)
    :precondition (>= (value ?c) 1)
    :effect (decrease (value ?c) 1)))
