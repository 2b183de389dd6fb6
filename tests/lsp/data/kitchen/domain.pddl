; A small kitchen: the robot picks dishes from the counter, washes them and puts them back.
(define (domain kitchen)
  (:requirements :strips :typing :negative-preconditions :constraints)
  (:types cup plate - dish
          dish - object)
  (:predicates
    ; the dish stands on the counter
    (on-counter ?d - dish)
    ; the dish has been washed
    (clean ?d - dish)
    ; the robot holds the dish
    (holding ?d - dish)
    ; the robot's hand is free
    (hand-empty))

  ; take a dish from the counter
  (:action pick
    :parameters (?d - dish)
    :precondition (and (on-counter ?d) (hand-empty))
    :effect (and (holding ?d) (not (on-counter ?d)) (not (hand-empty))))

  ; wash the dish in hand
  (:action wash
    :parameters (?d - dish)
    :precondition (holding ?d)
    :effect (clean ?d))

  (:action put-down
    :parameters (?d - dish)
    :precondition (holding ?d)
    :effect (and (on-counter ?d) (hand-empty) (not (holding ?d)))))
