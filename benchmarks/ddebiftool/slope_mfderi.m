function y=slope_mfderi(xx,p,varargin)
%% Exact multilinear forms D^j f(xx)[u1,...,uj] of the r.h.s. in slope_funcs.m
% (j = 1..5), for DDE-BIFTOOL's normal-form code (sys_mfderi). xx is
% n x 2 (current, delayed) at the equilibrium; each u_i holds the deviation
% of the state and the parameters at the same two times, as DDE-BIFTOOL's
% nmfm_try_mfderi passes it: an (n+np) x 2 array stacked into one column. The r.h.s. is a
% cubic polynomial in (m_y, s_y, u) and linear in z, z(t-tau) and s_x, so
% the forms are written out by hand: no finite differences enter l1 or l2.
% Parameter deviations are not supported (normal forms here use none).
ip.k=1; ip.tau=2; ip.a=4; ip.b=5; ip.cc=6; ip.v=8;
a=p(ip.a); b=p(ip.b); cc=p(ip.cc); v=p(ip.v); k=p(ip.k);
F1=3*a*v^2-2*b*v+cc;   % F'(v)
q=3*a*v-b;             % (3av-b)
n=size(xx,1);
my0=xx(2,1); sy0=xx(4,1); u0=xx(5,1);
U=cellfun(@(w)reshape(w,[],2),varargin,'UniformOutput',false);
if any(cellfun(@(w)any(any(w(n+1:end,:)~=0)),U))
    error('slope_mfderi: parameter deviations are not supported');
end
U=cellfun(@(w)w(1:n,:),U,'UniformOutput',false);
m=cellfun(@(w)w(2,1),U); s=cellfun(@(w)w(4,1),U); w=cellfun(@(w)w(5,1),U);
y=zeros(n,1);
switch numel(U)
    case 1
        u1=U{1};
        y(1)=m;                                                             % (6a)
        y(2)=-(F1+2*q*my0+3*a*my0^2+3*a*sy0)*m-(q+3*a*my0)*s...
            +k*(u1(1,2)-u1(1,1));                                           % (6b)
        y(3)=2*w;                                                           % (6c)
        y(4)=-(4*q*sy0+12*a*my0*sy0)*m...
            -(2*F1+4*q*my0+6*a*my0^2+12*a*sy0)*s-2*k*w;                     % (6d)
        y(5)=-(2*q*u0+6*a*my0*u0)*m-3*a*u0*s...
            -(F1+2*q*my0+3*a*my0^2+3*a*sy0)*w-k*u1(3,1)+s;                  % (6e)
    case 2
        y(2)=-(2*q+6*a*my0)*m(1)*m(2)-3*a*(m(1)*s(2)+m(2)*s(1));
        y(4)=-12*a*sy0*m(1)*m(2)-(4*q+12*a*my0)*(m(1)*s(2)+m(2)*s(1))...
            -12*a*s(1)*s(2);
        y(5)=-6*a*u0*m(1)*m(2)-(2*q+6*a*my0)*(m(1)*w(2)+m(2)*w(1))...
            -3*a*(s(1)*w(2)+s(2)*w(1));
    case 3
        y(2)=-6*a*m(1)*m(2)*m(3);
        y(4)=-12*a*(m(1)*m(2)*s(3)+m(1)*m(3)*s(2)+m(2)*m(3)*s(1));
        y(5)=-6*a*(m(1)*m(2)*w(3)+m(1)*m(3)*w(2)+m(2)*m(3)*w(1));
    case {4,5}
        % cubic r.h.s.: fourth and fifth derivatives vanish
    otherwise
        error('slope_mfderi: order %d not supported',numel(U));
end
end
