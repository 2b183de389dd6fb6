; A rover that drives between waypoints on a battery and recharges at a station.
(define (domain rover-numeric)
  (:requirements :strips :typing :numeric-fluents)
  (:types rover waypoint)
  (:predicates (at ?r - rover ?w - waypoint)
               (station ?w - waypoint)
               (sampled ?w - waypoint))
  (:functions (battery ?r - rover) (distance ?a ?b - waypoint) (energy-used))
  (:action drive
    :parameters (?r - rover ?from ?to - waypoint)
    :precondition (and (at ?r ?from) (>= (battery ?r) (distance ?from ?to)))
    :effect (and (not (at ?r ?from)) (at ?r ?to)
                 (decrease (battery ?r) (distance ?from ?to))
                 (increase (energy-used) (distance ?from ?to))))
  (:action recharge
    :parameters (?r - rover ?w - waypoint)
    :precondition (and (at ?r ?w) (station ?w) (< (battery ?r) 10))
    :effect (assign (battery ?r) 10))
  (:action sample
    :parameters (?r - rover ?w - waypoint)
    :precondition (and (at ?r ?w) (>= (battery ?r) 1))
    :effect (and (sampled ?w) (decrease (battery ?r) 1))))
